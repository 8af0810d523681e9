#include "gport/client/error.hpp"

namespace gport::client {
namespace {

std::string describe(int code, const std::string& message) {
    switch (code) {
        case static_cast<int>(ErrorCode::kTransport):
        case static_cast<int>(ErrorCode::kTimeout):
        case static_cast<int>(ErrorCode::kInterrupted):
            return message;
        case static_cast<int>(ErrorCode::kBadReply):
            return "unexpected reply from gportd: " + message;
        default:
            return message + " (gportd error " + std::to_string(code) + ")";
    }
}

}  // namespace

Error::Error(int code, const std::string& message)
    : std::runtime_error(describe(code, message)), code_(code), message_(message) {}

Error::Error(ErrorCode code, const std::string& message) : Error(static_cast<int>(code), message) {}

}  // namespace gport::client
