#include "gport/app/probe.hpp"

#include <cstdio>

#include "gport/base/exit_status.hpp"
#include "gport/daemon/probe.hpp"
#include "gport/daemon/serial_candidates.hpp"

namespace gport::app {

int run_probe(const std::vector<std::string>& devices, std::chrono::milliseconds listen) {
    const auto list = devices.empty() ? daemon::serial_candidates() : devices;
    if (list.empty()) {
        std::printf("gportd --probe: %s\n", daemon::candidates_hint(list).c_str());
        return kExitFailure;
    }
    std::printf("gportd --probe: listening %.1f s at 115200 baud on %zu device%s\n",
                std::chrono::duration<double>(listen).count(), list.size(),
                list.size() == 1 ? "" : "s");
    std::fflush(stdout);
    const auto results = daemon::probe_devices(list, listen);
    std::fputs(daemon::probe_report(results).c_str(), stdout);
    for (const auto& r : results) {
        if (r.kind == daemon::ProbeResult::Kind::kGport) {
            return kExitOk;
        }
    }
    return kExitFailure;
}

}  // namespace gport::app
