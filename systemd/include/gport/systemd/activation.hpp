// Socket activation (sd_listen_fds(3)).
#pragma once

#include <optional>
#include <stdexcept>

namespace gport::systemd {

// A socket passed by systemd that gportd cannot use.
class ActivationError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

// The listening socket systemd passed (LISTEN_FDS/LISTEN_PID), if any.
//
// Returns std::nullopt when none was passed: the daemon then binds its
// configured path itself. A passed socket takes precedence over the path.
// Exactly one listening AF_UNIX SOCK_STREAM socket is accepted; more than
// one, or another kind, throws ActivationError naming what was received and
// what gportd.socket must declare. The LISTEN_* variables are removed from
// the environment, so programs started by the daemon do not inherit them;
// the returned descriptor has FD_CLOEXEC set.
std::optional<int> activated_socket_fd();

}  // namespace gport::systemd
