#include "lines.hpp"

#include <algorithm>
#include <cstring>

#include "gport/base/json_depth.hpp"
#include "gport/client/error.hpp"

namespace gport::client::detail {
namespace {

// Past this the buffer grows once to the longest line and one read (rather
// than doubling, which would hold the old and the new copy at once); after a
// long line its memory is given back once it is empty.
constexpr std::size_t kKeepCapacity = 1 << 20;
// The most either transport reads at once.
constexpr std::size_t kLargestRead = 65536;
// How much of the parser's message a closing error quotes.
constexpr std::size_t kReasonChars = 200;

[[noreturn]] void refuse(const std::string& what) {
    throw Error(ErrorCode::kTransport, "gportd sent " + what + "; the connection is closed");
}

// The parser's message without its "[json.exception...] " prefix and the
// "; last read: ..." quote of the input (which may be long, or not UTF-8),
// in printable ASCII.
std::string parser_reason(const std::string& what) {
    auto reason = what.substr(what.find("] ") == std::string::npos ? 0 : what.find("] ") + 2);
    reason = reason.substr(0, reason.find("; last read"));
    if (reason.size() > kReasonChars) {
        reason.resize(kReasonChars);
    }
    for (auto& c : reason) {
        if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7e) {
            c = '?';
        }
    }
    return reason;
}

}  // namespace

void LineReader::append(const char* data, std::size_t size) {
    if (start_ > 0) {  // once per read: each byte is moved at most once
        buffer_.erase(0, start_);
        start_ = 0;
    }
    if (buffer_.empty() && buffer_.capacity() > kKeepCapacity) {
        std::string().swap(buffer_);
    }
    const std::size_t needed = buffer_.size() + size;
    if (needed > buffer_.capacity() && needed > kKeepCapacity) {
        buffer_.reserve(std::max(needed, limit_ + kLargestRead));
    }
    buffer_.append(data, size);
}

std::optional<std::string_view> LineReader::next() {
    const char* begin = buffer_.data() + start_;
    const std::size_t available = buffer_.size() - start_;
    const auto* newline =
        static_cast<const char*>(std::memchr(begin + scanned_, '\n', available - scanned_));
    const std::size_t length = newline ? static_cast<std::size_t>(newline - begin) : available;
    if (length > limit_) {
        refuse("a line longer than " + std::to_string(limit_) +
               " bytes (the client's line limit, kLineLimit)");
    }
    if (newline == nullptr) {
        scanned_ = available;
        return std::nullopt;
    }
    start_ += length + 1;
    scanned_ = 0;
    return std::string_view(begin, length);
}

void LineReader::clear() noexcept {
    buffer_.clear();
    start_ = 0;
    scanned_ = 0;
}

bool blank(std::string_view line) noexcept {
    return line.empty() || line == "\r";
}

nlohmann::json parse_line(std::string_view line) {
    if (base::nested_deeper_than(line, kNestingLimit)) {
        refuse("a line nested deeper than " + std::to_string(kNestingLimit) +
               " levels (the client's nesting limit, kNestingLimit)");
    }
    nlohmann::json message;
    try {
        message = nlohmann::json::parse(line);
    } catch (const nlohmann::json::parse_error& e) {
        refuse("a line that is not JSON (" + parser_reason(e.what()) + ")");
    }
    if (!message.is_object()) {
        refuse(std::string("a line that is not a JSON object (") + message.type_name() + ")");
    }
    return message;
}

}  // namespace gport::client::detail
