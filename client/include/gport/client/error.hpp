// The one error type of libgport-client: what gportd refused (its JSON-RPC
// error code and message) or why the connection failed (kTransport) or what
// the library could not understand (kBadReply) or that no reply came in
// time (kTimeout).
#pragma once

#include <stdexcept>
#include <string>

#include "gport/client/export.hpp"
#include "gport/contract/errors.hpp"

namespace gport::client {

// The codes of docs/api.md ("Error codes"), with the names and values of
// gport/contract/errors.hpp, plus three of the library's own.
enum class ErrorCode : int {
    kTransport = -1,    // cannot connect, or the connection broke / was closed
    kBadReply = -2,     // a reply the library does not understand (version mismatch?)
    kTimeout = -3,      // no reply within the call timeout (the connection stays usable)
    kInterrupted = -4,  // Client::set_interrupt's check said stop (1.6.0; the connection stays)
#define GPORT_CLIENT_ERROR_CODE(name, code, meaning) name = contract::rpc_error::name,
    GPORT_CONTRACT_ERROR_CODES(GPORT_CLIENT_ERROR_CODE)
#undef GPORT_CLIENT_ERROR_CODE
};

class GPORT_CLIENT_API Error : public std::runtime_error {
  public:
    Error(int code, const std::string& message);
    Error(ErrorCode code, const std::string& message);

    // The API code (e.g. -32003), or -1 / -2 / -3 / -4 for kTransport /
    // kBadReply / kTimeout / kInterrupted.
    int code() const noexcept { return code_; }
    bool is(ErrorCode code) const noexcept { return code_ == static_cast<int>(code); }
    // True when the connection is unusable: connect again.
    bool transport() const noexcept { return is(ErrorCode::kTransport); }
    // The message as gportd (or the library) gave it; what() adds the code.
    const std::string& message() const noexcept { return message_; }

  private:
    int code_;
    std::string message_;
};

}  // namespace gport::client
