#include "gport/systemd/activation.hpp"

#include <sys/socket.h>
#include <systemd/sd-daemon.h>

#include <cstring>
#include <string>

namespace gport::systemd {

namespace {

const char* const kWhatIsAllowed =
    "gportd accepts exactly one listening AF_UNIX stream socket "
    "(one ListenStream=/path line in its .socket unit, Accept=no)";

}  // namespace

std::optional<int> activated_socket_fd() {
    // unset_environment=1: children of the daemon must not believe the
    // sockets are theirs.
    const int count = sd_listen_fds(1);
    if (count < 0) {
        throw ActivationError(std::string("invalid socket activation variables (LISTEN_FDS, "
                                          "LISTEN_PID): ") +
                              std::strerror(-count));
    }
    if (count == 0) {
        return std::nullopt;
    }
    if (count > 1) {
        throw ActivationError("systemd passed " + std::to_string(count) + " sockets; " +
                              kWhatIsAllowed);
    }
    const int fd = SD_LISTEN_FDS_START;
    const int is_unix = sd_is_socket_unix(fd, SOCK_STREAM, 1, nullptr, 0);
    if (is_unix < 0) {
        throw ActivationError("cannot inspect the socket systemd passed (fd " + std::to_string(fd) +
                              "): " + std::strerror(-is_unix));
    }
    if (is_unix == 0) {
        throw ActivationError("the socket systemd passed (fd " + std::to_string(fd) +
                              ") is not a listening AF_UNIX stream socket; " + kWhatIsAllowed);
    }
    return fd;
}

}  // namespace gport::systemd
