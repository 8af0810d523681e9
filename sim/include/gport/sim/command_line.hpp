// gport-sim's command line: parsing into SimOptions, and the --help text.
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "gport/base/result.hpp"
#include "gport/sim/simulator.hpp"

namespace gport::sim {

inline constexpr int kExitUsage = 64;    // EX_USAGE: bad command line
inline constexpr int kExitOsError = 71;  // EX_OSERR: pty or link could not be made
inline constexpr int kExitNoInput = 66;  // EX_NOINPUT: recording unreadable

struct CommandLine {
    SimOptions options;  // options.trace is left empty: the tool decides where it goes
    bool trace = false;
    bool help = false;
};

// A command line gport-sim refuses: the message names the option and what it
// allows (printed with the usage hint, exit kExitUsage).
struct OptionError {
    std::string message;
};

// Parses the arguments after the program name. Accepts "--opt value" and
// "--opt=value".
Result<CommandLine, OptionError> parse_command_line(std::span<const std::string_view> args);

std::string help_text();

}  // namespace gport::sim
