// The gportd process: wires the core, the client socket, systemd and
// (with --simulate) the simulated gimbal around one event loop.
#pragma once

#include "gport/config/config.hpp"

namespace gport::daemon {

// Runs until SIGTERM or SIGINT; returns the process exit status.
int run_daemon(const config::Config& config);

}  // namespace gport::daemon
