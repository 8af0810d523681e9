// The JSON-RPC error codes of gportd's client API (docs/api.md, "Error
// codes"): the one list, one name per code. gportd answers with them, the
// core's CommandError carries them (daemon::ErrorCode), libgport-client's
// ErrorCode takes its values from them and the Python client's exceptions
// (gport/errors.py) are checked against them (tests/contract).
//
// Standard C++17, installed with libgport-client's headers.
#pragma once

namespace gport::contract {

// X(name, code, meaning) for each code, in the order of docs/api.md. The
// list is a macro so that the enum below and the tools that print or check
// the contract (tests/contract) read the same entries.
#define GPORT_CONTRACT_ERROR_CODES(X)                                                         \
    X(kParse, -32700, "parse error: not JSON, a number too large, nesting too deep")          \
    X(kInvalidRequest, -32600, "invalid request: not a JSON-RPC request, or a line too long") \
    X(kUnknownMethod, -32601, "unknown method")                                               \
    X(kInvalidParams, -32602, "invalid params: a field missing, unknown or out of range")     \
    X(kInternal, -32603, "internal error; also: the attitude channel cannot be made")         \
    X(kLinkDown, -32000, "gimbal link down: the serial device is not open, or no attitude")   \
    X(kPermission, -32001, "permission denied: this peer may only read")                      \
    X(kNoAnswer, -32002, "the gimbal did not answer")                                         \
    X(kBusy, -32003, "another client holds control")                                          \
    X(kNoSlot, -32004, "no slot for this connection (a limit, or idle); it is closed")        \
    X(kTooManyRequests, -32005, "too many requests: over the rate or the settings queue")     \
    X(kConfigInvalid, -32006, "the daemon's configuration is invalid: it serves nothing")

namespace rpc_error {

// Unscoped on purpose, inside a namespace of its own: rpc_error::kBusy is
// an int where the wire wants a number (JSON, comparisons), and the type
// rpc_error::Code where a value must be one of these (daemon::ErrorCode).
enum Code : int {
#define GPORT_CONTRACT_ERROR_ENUMERATOR(name, code, meaning) name = code,
    GPORT_CONTRACT_ERROR_CODES(GPORT_CONTRACT_ERROR_ENUMERATOR)
#undef GPORT_CONTRACT_ERROR_ENUMERATOR
};

}  // namespace rpc_error

}  // namespace gport::contract
