#include "stop_report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "lines.hpp"

namespace gport::bench {
namespace {

// The first zero-speed frame stamped at or after `from_ns` and before
// `until_ns`; 0 when there is none.
std::int64_t first_stop(const std::vector<ControlStamp>& frames, std::int64_t from_ns,
                        std::int64_t until_ns) {
    const auto at =
        std::lower_bound(frames.begin(), frames.end(), from_ns,
                         [](const ControlStamp& frame, std::int64_t t) { return frame.t_ns < t; });
    for (auto it = at; it != frames.end() && it->t_ns < until_ns; ++it) {
        if (!it->speed_nonzero) {
            return it->t_ns;
        }
    }
    return 0;
}

StopStats stats_of(const std::vector<StopSample>& samples, const std::vector<ControlStamp>& frames,
                   StopCause cause) {
    StopStats s;
    std::vector<double> ms;
    for (const auto& sample : samples) {
        if (sample.cause != cause) {
            continue;
        }
        ++s.count;
        const auto window_end = sample.cause_ns + std::int64_t{kStopTimeoutMs} * 1'000'000;
        const auto wire = sample.seen ? first_stop(frames, sample.before_ns, window_end) : 0;
        if (wire == 0) {
            ++s.lost;
            continue;
        }
        // A stop can reach the pty before the probe's stamp after write():
        // the probe may be preempted in between. That counts as no delay.
        ms.push_back(static_cast<double>(std::max<std::int64_t>(0, wire - sample.cause_ns)) / 1e6);
    }
    s.max_ms = ms.empty() ? 0 : *std::max_element(ms.begin(), ms.end());
    s.p50_ms = quantile(ms, 0.50);
    s.p99_ms = quantile(ms, 0.99);
    return s;
}

std::string line_of(const char* cause, const StopStats& s) {
    return fmt::format(
        "  stop by {:<10} | n {:>4} | lost {:>3} | p50 {:>7.3f} ms | p99 {:>7.3f} ms "
        "| max {:>7.3f} ms\n",
        cause, s.count, s.lost, s.p50_ms, s.p99_ms, s.max_ms);
}

nlohmann::json json_of(const StopStats& s) {
    return {{"count", s.count},
            {"lost", s.lost},
            {"p50_ms", s.p50_ms},
            {"p99_ms", s.p99_ms},
            {"max_ms", s.max_ms}};
}

}  // namespace

StopReport stops_of(const std::vector<StopSample>& samples,
                    const std::vector<ControlStamp>& frames) {
    StopReport r;
    r.request = stats_of(samples, frames, StopCause::kStopRequest);
    r.disconnect = stats_of(samples, frames, StopCause::kDisconnect);
    return r;
}

std::string stop_table(const StopReport& report) {
    if (report.per_cause == 0) {
        return "";
    }
    return line_of("`stop`", report.request) + line_of("close", report.disconnect);
}

nlohmann::json to_json(const StopReport& report) {
    nlohmann::json j = {{"per_cause", report.per_cause},
                        {"stop_request", json_of(report.request)},
                        {"disconnect", json_of(report.disconnect)}};
    if (!report.error.empty()) {
        j["error"] = report.error;
    }
    return j;
}

}  // namespace gport::bench
