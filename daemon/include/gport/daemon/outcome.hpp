// What a command to the daemon core returns: a value, or an error whose code
// is one of the client API's error codes (docs/api.md, "Error codes"; the
// list is gport/contract/errors.hpp).
#pragma once

#include <string>

#include "gport/base/result.hpp"
#include "gport/contract/errors.hpp"

namespace gport::daemon {

// The core answers with kInvalidParams, kLinkDown, kPermission, kNoAnswer,
// kBusy and kTooManyRequests; ipc sends the code as it is.
using ErrorCode = contract::rpc_error::Code;

struct CommandError {
    ErrorCode code;
    std::string message;
};

using Done = gport::Done;

// What every command returns; one template in the tree (gport/base/result.hpp).
template <typename T>
using Outcome = gport::Result<T, CommandError>;

}  // namespace gport::daemon
