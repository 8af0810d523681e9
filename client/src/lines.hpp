// The reading half of both transports (Connection, AsyncClient): the bytes
// read from gportd split into lines, and each line checked and parsed,
// within the limits of gport/client/limits.hpp. A hostile server cannot
// make the client hold more than one line's limit and one read, rescan what
// it already scanned, or recurse: a line over kLineLimit, nested deeper than
// kNestingLimit, not JSON or not a JSON object throws Error (kTransport)
// naming what was wrong, and the transport ends the connection.
//
// Internal to the library (not installed).
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

#include "gport/client/limits.hpp"

namespace gport::client::detail {

class LineReader {
  public:
    explicit LineReader(std::size_t limit = kLineLimit) : limit_(limit) {}

    // Adds bytes read from the socket (after dropping the lines returned).
    void append(const char* data, std::size_t size);

    // The next complete line, without its newline, valid until the next
    // append() or clear(); empty when no line is complete. Throws Error
    // (kTransport) naming the limit once the line being read is longer.
    // Each byte is scanned for the newline once.
    std::optional<std::string_view> next();

    void clear() noexcept;

  private:
    std::string buffer_;
    std::size_t start_ = 0;    // the first byte not returned yet
    std::size_t scanned_ = 0;  // bytes from start_ known to hold no newline
    std::size_t limit_;
};

// True for a line to skip: empty, or only the '\r' of a CRLF.
bool blank(std::string_view line) noexcept;

// The JSON object of one line from gportd. Throws Error (kTransport) naming
// what was wrong: nested deeper than kNestingLimit (checked before
// parsing), not JSON (with the parser's reason: syntax, ill-formed UTF-8),
// or not an object.
nlohmann::json parse_line(std::string_view line);

}  // namespace gport::client::detail
