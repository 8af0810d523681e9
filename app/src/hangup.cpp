#include "hangup.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <csignal>

namespace gport::app {
namespace {

// Whether this process has a controlling terminal now.
bool has_controlling_terminal() {
    const int fd = ::open("/dev/tty", O_RDWR | O_NOCTTY | O_CLOEXEC);
    if (fd < 0) {
        return false;
    }
    ::close(fd);
    return true;
}

bool sighup_ignored() {
    struct sigaction current {};
    return ::sigaction(SIGHUP, nullptr, &current) == 0 && current.sa_handler == SIG_IGN;
}

}  // namespace

HangupRule HangupRule::at_start() {
    return HangupRule(!sighup_ignored() && has_controlling_terminal());
}

bool HangupRule::is_hangup() const {
    return watch_terminal_ && !has_controlling_terminal();
}

}  // namespace gport::app
