// gportd with a configuration it cannot load, started by socket activation
// (docs/operations.md, "A bad configuration under systemd").
//
// Exiting there would not help: the client that triggered the start is still
// waiting on the socket systemd holds, so systemd starts gportd again at
// once, and a client retrying in a loop (gport-mavlink, a flight script)
// drives the service into its start limit, after which the socket itself
// fails and even a fixed file needs `systemctl reset-failed`. Instead gportd
// stays up on the socket it was given and answers every request with
// -32006 naming the problem, until it is stopped (systemctl restart with a
// fixed file) or reloaded (SIGHUP: the file is read again; once it loads,
// gportd exits kExitConfigFixed so that systemd starts it with it).
//
// Bounded: at most kMaxConnections at a time (others are closed at once),
// one request line of at most kMaxLine bytes each, kReadTimeout to send it;
// the problem is logged once, and once per reload.
#pragma once

#include <chrono>
#include <cstddef>
#include <optional>
#include <string>

#include "gport/config/command_line.hpp"

namespace gport::app {

struct ConfigErrorServing {
    static constexpr std::size_t kMaxConnections = 16;
    static constexpr std::size_t kMaxLine = 64 * 1024;
    static constexpr std::chrono::seconds kReadTimeout{2};
    // EX_TEMPFAIL: the unit's Restart=on-failure starts gportd again.
    static constexpr int kExitConfigFixed = 75;
};

// When systemd passed gportd its socket: serves `problem` (the loader's
// text) on it until a signal ends it, and returns the exit status: 0 on
// SIGTERM/SIGINT, kExitConfigFixed when a SIGHUP found the file loadable,
// config::kExitConfig when the passed socket is unusable. std::nullopt when
// gportd was not socket-activated (it then exits kExitConfig, as ever).
std::optional<int> serve_config_error_if_activated(const std::string& problem,
                                                   const config::CommandLine& command_line);

}  // namespace gport::app
