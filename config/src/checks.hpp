// Checks shared by the config file and the command line, so that a value is
// judged the same way wherever it comes from. Each returns the problem, or
// nothing when the value is fine; the caller prefixes the key or option.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace gport::config::detail {

// "trace, debug, info, warn, error, critical, off"
std::string_view log_levels_text();

std::optional<std::string> check_log_level(std::string_view level);
std::optional<std::string> check_device_path(std::string_view path);
std::optional<std::string> check_socket_path(std::string_view path);
// The capture log's directory: --state-dir, captures.dir.
std::optional<std::string> check_state_dir(std::string_view path);

// `text` as a JSON string literal, cut short if long: safe to print whatever
// bytes it holds.
std::string json_quoted(std::string_view text);

}  // namespace gport::config::detail
