// The gportd process: wires the core, the client socket, systemd and
// (with --simulate) the simulated gimbal around one event loop.
#pragma once

#include "gport/config/command_line.hpp"
#include "gport/config/config.hpp"

namespace gport::app {

// Runs until SIGTERM, SIGINT or SIGQUIT; returns the process exit status.
// SIGHUP re-reads the configuration as `command_line` names it.
int run_daemon(const config::Config& config, const config::CommandLine& command_line);

}  // namespace gport::app
