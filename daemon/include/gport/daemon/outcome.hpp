// What a command to the daemon core returns: a value, or an error whose code
// maps one-to-one onto the client API's error codes (docs/api.md, "Error
// codes").
#pragma once

#include <string>
#include <utility>
#include <variant>

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

struct Done {};

template <typename T>
class [[nodiscard]] Outcome {
  public:
    Outcome(T value) : v_(std::move(value)) {}             // NOLINT: implicit by design
    Outcome(CommandError error) : v_(std::move(error)) {}  // NOLINT: implicit by design

    bool ok() const { return std::holds_alternative<T>(v_); }
    explicit operator bool() const { return ok(); }
    const T& value() const { return std::get<T>(v_); }
    const T* operator->() const { return &value(); }
    const CommandError& error() const { return std::get<CommandError>(v_); }

  private:
    std::variant<T, CommandError> v_;
};

}  // namespace gport::daemon
