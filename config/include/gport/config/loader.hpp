// Reading gportd's configuration file into a Config.
//
// The file is JSON with comments; every section and key is optional and
// missing ones keep the defaults in config.hpp. Unknown keys, wrong types,
// out-of-range values and inconsistent pairs are errors; all of them are
// reported together, each naming the key path (e.g. "keepalive.max_duration_ms")
// and what is allowed. The reference is docs/configuration.md.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "gport/config/command_line.hpp"
#include "gport/config/config.hpp"
#include "gport/config/result.hpp"

namespace gport::config {

// Files larger than this are refused: a config is a few kilobytes, and the
// limit keeps a mistyped path such as /dev/zero from exhausting memory.
inline constexpr std::size_t kMaxConfigBytes = 1024 * 1024;

// Parses `text` (the contents of a config file) on top of the defaults.
// `origin` names the text in messages, usually the file's path.
Result<Config> load_config_text(std::string_view text, std::string_view origin);

// Reads and parses the file at `path`; a missing or unreadable file is an error.
Result<Config> load_config_file(const std::string& path);

// What the daemon does at start: reads --config FILE (an error if it is
// missing) or else `default_path`, by default default_config_path() (built-in
// defaults if it does not exist),
// then applies the command-line overrides (--device, --socket, --log-level,
// --simulate). Errors here are configuration errors: exit with kExitConfig.
Result<Config> load_config(const CommandLine& command_line, std::string_view default_path);
Result<Config> load_config(const CommandLine& command_line);

}  // namespace gport::config
