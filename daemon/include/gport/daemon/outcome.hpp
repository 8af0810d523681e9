// What a command to the daemon core returns: a value, or an error whose code
// maps one-to-one onto the client API's error codes (docs/api.md, "Error
// codes").
#pragma once

#include <string>

#include "gport/base/result.hpp"

namespace gport::daemon {

enum class ErrorCode {
    kInvalidParams,  // -32602: a parameter outside what is allowed
    kLinkDown,       // -32000: the serial device is not open
    kPermission,     // -32001: this peer may only read
    kNoAnswer,       // -32002: the gimbal did not answer
    kBusy,           // -32003: another client holds control
    kTooMany,        // -32005: too many requests from this client (or in total)
};

struct CommandError {
    ErrorCode code;
    std::string message;
};

using Done = gport::Done;

// What every command returns; one template in the tree (gport/base/result.hpp).
template <typename T>
using Outcome = gport::Result<T, CommandError>;

}  // namespace gport::daemon
