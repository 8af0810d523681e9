// A value or every problem found in the input that should have produced it.
//
// Configuration is fixed by a person editing a file, so the loader reports all
// problems at once (one message each) instead of stopping at the first one.
#pragma once

#include <cassert>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace gport::config {

// One message per problem; each names the key or option and what is allowed.
struct Errors {
    std::vector<std::string> messages;
};

template <typename T>
class [[nodiscard]] Result {
  public:
    Result(T value) : v_(std::move(value)) {}        // NOLINT: implicit by design
    Result(Errors errors) : v_(std::move(errors)) {  // NOLINT: implicit by design
        assert(!std::get<Errors>(v_).messages.empty());
    }

    bool ok() const { return std::holds_alternative<T>(v_); }
    explicit operator bool() const { return ok(); }

    const T& value() const& { return std::get<T>(v_); }
    T&& value() && { return std::get<T>(std::move(v_)); }
    const T& operator*() const& { return value(); }
    const T* operator->() const { return &value(); }

    // Empty when ok().
    const std::vector<std::string>& errors() const {
        static const std::vector<std::string> kNone;
        return ok() ? kNone : std::get<Errors>(v_).messages;
    }

    // The messages one per line, ready to print to stderr or the journal.
    std::string error_text() const {
        std::string text;
        for (const auto& message : errors()) {
            text += message;
            text += '\n';
        }
        return text;
    }

  private:
    std::variant<T, Errors> v_;
};

}  // namespace gport::config
