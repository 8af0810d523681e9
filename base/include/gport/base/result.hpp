// gport::Result<T, E>: a value, or the reason there is none.
//
// The one way the tree says "it failed" for input that users, files, devices
// or peers control. It is modelled on C++23's std::expected (value(), error(),
// has_value(), operator bool, operator*, operator->, gport::unexpected), small
// enough to read at once. Each layer picks its own E: protocol::Error,
// config::Errors, daemon::CommandError, cli::UsageError, sim::OptionError.
// Exceptions stay for programming errors and constructors.
//
// A Result converts implicitly from a T and from an E, so `return value;` and
// `return Error{...};` both read naturally; `gport::unexpected(e)` says it
// explicitly (and is what std::expected would need). T and E must differ.
// Asking a Result for the alternative it does not hold is a programming error
// and throws std::bad_variant_access.
#pragma once

#include <type_traits>
#include <utility>
#include <variant>

namespace gport {

// An error on its way into a Result, as std::unexpected.
template <typename E>
class Unexpected {
  public:
    explicit Unexpected(E error) : error_(std::move(error)) {}
    const E& error() const& { return error_; }
    E&& error() && { return std::move(error_); }

  private:
    E error_;
};

template <typename E>
Unexpected<std::decay_t<E>> unexpected(E&& error) {
    return Unexpected<std::decay_t<E>>(std::forward<E>(error));
}

template <typename T, typename E>
class [[nodiscard]] Result {
    static_assert(!std::is_same_v<std::decay_t<T>, std::decay_t<E>>,
                  "a Result's value and error types must differ");

  public:
    using value_type = T;
    using error_type = E;

    Result(T value) : v_(std::in_place_index<0>, std::move(value)) {}  // NOLINT: implicit
    Result(E error) : v_(std::in_place_index<1>, std::move(error)) {}  // NOLINT: implicit
    template <typename G>
    requires std::is_constructible_v<E, G> Result(
        Unexpected<G> error)  // NOLINT: implicit, as std::expected
        : v_(std::in_place_index<1>, std::move(error).error()) {}

    bool has_value() const { return v_.index() == 0; }
    // The spelling the tree used before this header; the same as has_value().
    bool ok() const { return has_value(); }
    explicit operator bool() const { return has_value(); }

    const T& value() const& { return std::get<0>(v_); }
    T& value() & { return std::get<0>(v_); }
    T&& value() && { return std::get<0>(std::move(v_)); }

    const E& error() const& { return std::get<1>(v_); }
    E& error() & { return std::get<1>(v_); }
    E&& error() && { return std::get<1>(std::move(v_)); }

    const T& operator*() const& { return value(); }
    T& operator*() & { return value(); }
    T&& operator*() && { return std::move(*this).value(); }
    const T* operator->() const { return &value(); }
    T* operator->() { return &value(); }

    template <typename U>
    T value_or(U&& fallback) const& {
        return has_value() ? value() : static_cast<T>(std::forward<U>(fallback));
    }

  private:
    std::variant<T, E> v_;
};

// The value of a Result that only succeeds or fails: Result<Done, E>.
struct Done {};

}  // namespace gport
