// The probe both relays share: N times, start a motion through the relay,
// wait until the gimbal has it (or 50 ms), send the stop, and time the first
// zero-speed 0x85 that reaches the gimbal's wire after it (LineSim's stamps).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

namespace gport::bench {
class LineSim;
}

namespace gport::bench::relay {

// A stop not on the wire this long after it was sent is lost.
inline constexpr std::int64_t kLostAfterNs = 1'000'000'000;
// After a lost stop the probe waits this long (from the stop) for its zero
// speed before the next motion: stops queued in the relay reach the wire in
// order, and a late one must not be taken for the next one's.
inline constexpr std::int64_t kLateWaitNs = 5'000'000'000;

struct ProbeHooks {
    std::function<void()> start_motion;
    std::function<void(int)> send_stop;  // the stop's number, from 0
    std::function<void()> idle;          // called every millisecond or so while waiting
};

struct ProbeResult {
    int sent = 0;
    std::vector<double> delays_ms;  // one per stop seen on the wire in time
    std::vector<double> late_ms;    // lost stops on the wire later, within kLateWaitNs
    int lost() const { return sent - static_cast<int>(delays_ms.size()); }
};

ProbeResult run_probe(LineSim& sim, int stops, int spacing_ms, const ProbeHooks& hooks);

}  // namespace gport::bench::relay
