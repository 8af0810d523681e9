// Helpers shared by the config tests: loading text under a fixed origin and
// matching error messages by the pieces that matter to a user.
#pragma once

#include <gmock/gmock.h>

#include <string>
#include <string_view>

#include "gport/config/loader.hpp"

namespace gport::config::test {

inline constexpr std::string_view kOrigin = "test.json";

inline Result<Config> load(std::string_view text) {
    return load_config_text(text, kOrigin);
}

// Loads `text`, expects it to fail, and returns the messages.
inline std::vector<std::string> errors_of(std::string_view text) {
    auto result = load(text);
    EXPECT_FALSE(result.ok()) << "expected errors for: " << text;
    return result.error().messages;
}

// An error message that holds every one of the given pieces.
template <typename... Pieces>
auto ErrorWith(Pieces... pieces) {
    return ::testing::AllOf(::testing::HasSubstr(std::string(pieces))...);
}

}  // namespace gport::config::test
