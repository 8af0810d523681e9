// What the stop probe measured (bench_e2e --stops N), per cause: how many
// stops, how many never reached the pty, and the latency from the cause to
// the first zero-speed 0x85 frame on the pty.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "fake_gimbal.hpp"
#include "stop_probe.hpp"

namespace gport::bench {

struct StopStats {
    std::uint64_t count = 0;  // motions ended by this cause
    std::uint64_t lost = 0;   // no zero speed on the pty within kStopTimeoutMs
    double p50_ms = 0;
    double p99_ms = 0;
    double max_ms = 0;
};

struct StopReport {
    int per_cause = 0;     // --stops; 0 = the probe did not run
    StopStats request;     // ended by a `stop` request
    StopStats disconnect;  // ended by closing the owner's connection
    std::string error;     // the probe failed before its last cycle ("" = it did not)
};

// Matches each cause with the first zero-speed frame stamped after it.
StopReport stops_of(const std::vector<StopSample>& samples,
                    const std::vector<ControlStamp>& frames);

// Two table lines, one per cause (empty when the probe did not run).
std::string stop_table(const StopReport& report);
nlohmann::json to_json(const StopReport& report);

}  // namespace gport::bench
