// gportd's command line (CLI11, with the conventions of gport/base/args.hpp):
//
//   gportd [--config FILE] [--device PATH] [--socket PATH] [--log-level LEVEL]
//          [--state-dir DIR] [--simulate] [--help] [--version]
//   gportd --probe [DEVICE...]
//
// Options with a value accept both "--opt VALUE" and "--opt=VALUE"; when an
// option is repeated the last one wins. Values given here override the file.
//
// Exit statuses the daemon uses (sysexits.h), defined here only:
//   kExitUsage  (64, EX_USAGE)  parse_command_line() failed;
//   kExitConfig (78, EX_CONFIG) load_config() failed, or socket activation
//                               was misconfigured.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "gport/base/exit_status.hpp"
#include "gport/config/result.hpp"

namespace gport::config {

using gport::kExitConfig;
using gport::kExitUsage;

// The file read when --config is not given (its absence means built-in
// defaults): gportd.json in the configuration directory of the prefix the
// running gportd was installed to, as GNUInstallDirs maps it:
//   /usr/bin/gportd (the .deb)        -> /etc/gportd/gportd.json;
//   /opt/NAME/bin/gportd              -> /etc/opt/NAME/gportd/gportd.json;
//   PREFIX/bin/gportd (anything else) -> PREFIX/etc/gportd/gportd.json;
// the directory the build was configured with if it forced one
// (GPORT_CONFIG_DIR). A gportd outside an installed bin/ (the build tree)
// reads kFallbackConfigPath.
std::string default_config_path();

// `program` is where the running gportd is (/proc/self/exe); `bindir` and
// `sysconfdir` are the install layout's (CMAKE_INSTALL_BINDIR and
// CMAKE_INSTALL_SYSCONFDIR, relative or absolute); `forced` is the configured
// directory, empty if none. default_config_path() is this on the real values.
std::string default_config_path_for(const std::string& program, const std::string& bindir,
                                    const std::string& sysconfdir, const std::string& forced);

inline constexpr std::string_view kFallbackConfigPath = "/etc/gportd/gportd.json";

struct CommandLine {
    std::optional<std::string> config_path;  // --config; unset: the default file, if any
    std::optional<std::string> device;       // --device: overrides serial.device
    std::optional<std::string> socket_path;  // --socket: overrides socket.path
    std::optional<std::string> log_level;    // --log-level: overrides log.level
    std::optional<std::string> state_dir;    // --state-dir: overrides captures.dir
    bool simulate = false;                   // --simulate: use the built-in simulated gimbal
    // --probe [DEVICE...]: listen for a G-Port on DEVICEs (none given: the
    // usual serial devices), report, exit (gport/app/probe.hpp).
    std::optional<std::vector<std::string>> probe;
    bool help = false;     // --help / -h: print usage() and exit 0
    bool version = false;  // --version: print version_text() and exit 0
};

// `args` is argv as given to main (args[0], the program name, is skipped).
// Unknown options, missing values and invalid values are usage errors
// (CLI11 stops at the first; the message names the option and what is allowed).
Result<CommandLine> parse_command_line(std::span<const char* const> args);

// The --help text, ending with a newline.
std::string usage();

// "gportd <version>", ending with a newline.
std::string version_text();

}  // namespace gport::config
