// gport-web's program: the options, the token file, the listener, the
// connection to gportd, one io_context on one thread until SIGINT/SIGTERM.
#pragma once

#include <span>
#include <string>

namespace gport::web {

// The exit status (gport/base/exit_status.hpp): 0 after a signal, 64 bad
// command line, 66 token file refused, 71 cannot listen.
int run(std::span<const std::string> args);

}  // namespace gport::web
