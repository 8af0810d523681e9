// Runs one parsed gportctl invocation against the daemon and returns the
// exit status (see options.hpp).
#pragma once

#include <functional>
#include <ostream>

#include "gport/cli/options.hpp"

namespace gport::cli {

// Which of the streams are terminals: on `out`, speed --for updates one
// progress line in place; on `err`, watch says what it watches.
struct Terminals {
    bool out = false;
    bool err = false;
};

// `interrupted` reports SIGINT/SIGTERM; watch and speed end on it (speed
// after sending stop).
int run(const Invocation& invocation, std::ostream& out, std::ostream& err,
        std::function<bool()> interrupted, Terminals terminals = {});

// Parses argv (without argv[0]) and runs it: the whole of gportctl.
int main_with(const std::vector<std::string>& args, const char* env_socket, std::ostream& out,
              std::ostream& err, std::function<bool()> interrupted, Terminals terminals = {});

}  // namespace gport::cli
