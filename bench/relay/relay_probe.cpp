#include "relay_probe.hpp"

#include <chrono>
#include <cstdint>
#include <thread>
#include <utility>

#include "../e2e/line_sim.hpp"
#include "../e2e/posix.hpp"

namespace gport::bench::relay {
namespace {

constexpr std::int64_t kMotionWaitNs = 50'000'000;

// Calls idle() about every millisecond until `until` (CLOCK_MONOTONIC ns)
// or `done()` holds.
template <typename Done>
void wait_until(std::int64_t until, const ProbeHooks& hooks, Done&& done) {
    while (!done() && now_ns() < until) {
        if (hooks.idle) {
            hooks.idle();
        }
        std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
}

// The stamp of the first zero-speed frame from number `first` on that
// arrived at or after t0 and within `limit_ns` of it; -1 when none did.
std::int64_t first_stop_after(const LineSim& sim, std::uint64_t first, std::int64_t t0,
                              std::int64_t limit_ns = kLostAfterNs) {
    for (std::uint64_t n = first;; ++n) {
        const std::int64_t stamp = sim.stop_time(n);
        if (stamp < 0 || stamp > t0 + limit_ns) {
            return -1;
        }
        if (stamp >= t0) {
            return stamp;
        }
    }
}

}  // namespace

ProbeResult run_probe(LineSim& sim, int stops, int spacing_ms, const ProbeHooks& hooks) {
    std::vector<std::pair<std::uint64_t, std::int64_t>> sent;  // (first zero speed to look at, t0)
    for (int i = 0; i < stops; ++i) {
        wait_until(now_ns() + std::int64_t{spacing_ms} * 1'000'000, hooks, [] { return false; });
        const auto speeds = sim.speeds_seen();
        hooks.start_motion();
        wait_until(now_ns() + kMotionWaitNs, hooks, [&] { return sim.speeds_seen() > speeds; });
        const auto first = sim.stops_seen();
        const auto t0 = now_ns();
        hooks.send_stop(i);  // may block (an HTTP request) past the whole wait
        sent.emplace_back(first, t0);
        // The trace reaches LineSim a little after the stamp: look 50 ms longer.
        wait_until(t0 + kLostAfterNs + 50'000'000, hooks,
                   [&] { return first_stop_after(sim, first, t0) >= 0; });
        wait_until(t0 + kLateWaitNs, hooks,
                   [&] { return first_stop_after(sim, first, t0, kLateWaitNs) >= 0; });
    }
    // Judged at the end, from the stamps alone: a stop is lost when no zero
    // speed reached the wire within kLostAfterNs of it (the next stop was
    // sent later than that, so its frame cannot count for this one), late
    // when one did within kLateWaitNs.
    ProbeResult result;
    result.sent = stops;
    for (const auto& [first, t0] : sent) {
        if (const auto stamp = first_stop_after(sim, first, t0); stamp >= 0) {
            result.delays_ms.push_back(static_cast<double>(stamp - t0) / 1e6);
        } else if (const auto late = first_stop_after(sim, first, t0, kLateWaitNs); late >= 0) {
            result.late_ms.push_back(static_cast<double>(late - t0) / 1e6);
        }
    }
    return result;
}

}  // namespace gport::bench::relay
