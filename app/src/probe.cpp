#include "gport/app/probe.hpp"

#include <sys/signalfd.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstring>

#include "gport/base/exit_status.hpp"
#include "gport/daemon/probe.hpp"
#include "gport/daemon/serial_candidates.hpp"

namespace gport::app {
namespace {

// Ctrl-C, a hang-up or a kill while the probe listens ends the listening,
// not the process at once: the signals are held back (blocked) and watched
// through a signalfd, the devices' settings are put back, the report is
// printed, and then the signal is let through and takes its usual course.
class HeldSignals {
  public:
    HeldSignals() {
        ::sigemptyset(&held_);
        for (const int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT}) {
            ::sigaddset(&held_, sig);
        }
        ::sigprocmask(SIG_BLOCK, &held_, &before_);
        fd_ = ::signalfd(-1, &held_, SFD_NONBLOCK | SFD_CLOEXEC);
    }
    ~HeldSignals() {
        if (fd_ >= 0) {
            ::close(fd_);
        }
        ::sigprocmask(SIG_SETMASK, &before_, nullptr);  // a held signal is delivered now
    }
    HeldSignals(const HeldSignals&) = delete;
    HeldSignals& operator=(const HeldSignals&) = delete;

    int fd() const { return fd_; }
    // The signal that came, if one did (left pending, for its delivery).
    int pending() const {
        sigset_t now;
        ::sigpending(&now);
        for (const int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT}) {
            if (::sigismember(&now, sig) == 1) {
                return sig;
            }
        }
        return 0;
    }

  private:
    sigset_t held_{};
    sigset_t before_{};
    int fd_ = -1;
};

}  // namespace

int run_probe(const std::vector<std::string>& devices, std::chrono::milliseconds listen) {
    const auto list = devices.empty() ? daemon::serial_candidates() : devices;
    if (list.empty()) {
        std::printf("gportd --probe: %s\n", daemon::candidates_hint(list).c_str());
        return kExitFailure;
    }
    HeldSignals signals;
    std::printf("gportd --probe: listening %.1f s at 115200 baud on %zu device%s\n",
                std::chrono::duration<double>(listen).count(), list.size(),
                list.size() == 1 ? "" : "s");
    std::fflush(stdout);
    const auto results = daemon::probe_devices(list, listen, signals.fd());
    if (const int sig = signals.pending()) {
        std::printf("gportd --probe: interrupted (SIG%s): stopped listening, settings put back\n",
                    ::sigabbrev_np(sig));
    }
    std::fputs(daemon::probe_report(results).c_str(), stdout);
    std::fflush(stdout);
    for (const auto& r : results) {
        if (r.kind == daemon::ProbeResult::Kind::kGport) {
            return kExitOk;
        }
    }
    return kExitFailure;
}

}  // namespace gport::app
