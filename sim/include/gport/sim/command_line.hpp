// gport-sim's command line: parsing into SimOptions, and the --help text.
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "gport/base/exit_status.hpp"
#include "gport/base/result.hpp"
#include "gport/sim/simulator.hpp"

namespace gport::sim {

using gport::kExitNoInput;  // a recording cannot be read
using gport::kExitOsError;  // the pty or the link cannot be made
using gport::kExitUsage;

struct CommandLine {
    SimOptions options;  // options.trace is left empty: the tool decides where it goes
    bool trace = false;
    bool help = false;     // -h/--help: print help_text()
    bool version = false;  // --version: print "gport-sim <version>"
};

// A command line gport-sim refuses: the message names the option and what it
// allows (printed with the usage hint, exit kExitUsage).
struct OptionError {
    std::string message;
};

// Parses the arguments after the program name with CLI11, as gportd and
// gportctl do (gport/base/args.hpp): "--opt value" and "--opt=value".
Result<CommandLine, OptionError> parse_command_line(std::span<const std::string_view> args);

std::string help_text();

// "gport-sim <version>", ending with a newline.
std::string version_text();

}  // namespace gport::sim
