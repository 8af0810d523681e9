#include "report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "lines.hpp"

namespace gport::bench {
namespace {

std::string mib(long kib) {
    return fmt::format("{:.1f}", static_cast<double>(kib) / 1024.0);
}

}  // namespace

DeliveryStats delivery_of(const std::vector<Subscriber>& subscribers,
                          std::uint32_t frames_written) {
    DeliveryStats d;
    for (const auto& s : subscribers) {
        d.expected += frames_written;
        d.delivered += static_cast<std::uint64_t>(std::count_if(
            s.receipts.begin(), s.receipts.end(),
            [&](const Receipt& r) { return r.counter >= 1 && r.counter <= frames_written; }));
        d.reported_dropped += s.reported_dropped;
        d.out_of_order += s.out_of_order;
        d.subscribers_closed += s.closed ? 1 : 0;
    }
    d.missing = d.expected - std::min(d.expected, d.delivered);
    return d;
}

LatencyStats latency_of(const std::vector<Subscriber>& subscribers,
                        const std::vector<std::int64_t>& write_times) {
    std::vector<std::int64_t> ns;
    std::vector<std::int64_t> first(write_times.size(), INT64_MAX);
    for (const auto& s : subscribers) {
        for (const auto& r : s.receipts) {
            if (r.counter >= 1 && r.counter < write_times.size() && write_times[r.counter] != 0) {
                const auto latency = r.t_ns - write_times[r.counter];
                ns.push_back(latency);
                first[r.counter] = std::min(first[r.counter], latency);
            }
        }
    }
    LatencyStats l;
    l.samples = ns.size();
    if (ns.empty()) {
        return l;
    }
    std::erase(first, INT64_MAX);
    l.first_p99_us = static_cast<double>(quantile(first, 0.99)) / 1e3;
    l.first_p50_us = static_cast<double>(quantile(first, 0.50)) / 1e3;
    l.max_us = static_cast<double>(*std::max_element(ns.begin(), ns.end())) / 1e3;
    l.p999_us = static_cast<double>(quantile(ns, 0.999)) / 1e3;
    l.p99_us = static_cast<double>(quantile(ns, 0.99)) / 1e3;
    l.p50_us = static_cast<double>(quantile(ns, 0.50)) / 1e3;
    return l;
}

KeepaliveStats keepalive_of(const std::vector<ControlStamp>& frames, std::int64_t from_ns,
                            std::int64_t to_ns, double period_ms,
                            const std::vector<std::int64_t>& motion_starts) {
    const auto restarted = [&](std::int64_t from, std::int64_t to) {
        const auto at = std::upper_bound(motion_starts.begin(), motion_starts.end(), from);
        return at != motion_starts.end() && *at < to;
    };
    std::vector<double> deviations;
    std::int64_t previous = 0;
    for (const auto& f : frames) {
        if (!f.speed_nonzero || f.t_ns < from_ns || f.t_ns > to_ns) {
            previous = 0;  // a stop, or outside the window: no gap to measure
            continue;
        }
        if (previous != 0 && !restarted(previous, f.t_ns)) {
            deviations.push_back(
                std::abs(static_cast<double>(f.t_ns - previous) / 1e6 - period_ms));
        }
        previous = f.t_ns;
    }
    KeepaliveStats k;
    k.intervals = deviations.size();
    if (deviations.empty()) {
        return k;
    }
    k.max_dev_ms = *std::max_element(deviations.begin(), deviations.end());
    k.p99_dev_ms = quantile(deviations, 0.99);
    k.p50_dev_ms = quantile(deviations, 0.50);
    return k;
}

std::string table_header() {
    return fmt::format(
        "{:>5} {:>5} {:>5} | {:>6} {:>9} {:>7} | {:>8} {:>8} {:>8} {:>8} | {:>6} {:>6} {:>6} | "
        "{:>6} {:>6} {:>4} | {:>7} | {}\n",
        "rate", "subs", "flood", "frames", "lines", "miss%", "p50 µs", "p99 µs", "max µs",
        "1st p99", "cpu%", "RSS", "HWM", "ka p99", "ka max", "n", "req/s", "load (start)");
}

std::string table_row(const CellResult& r) {
    const auto& d = r.delivery;
    const double miss =
        d.expected == 0 ? 0.0
                        : 100.0 * static_cast<double>(d.missing) / static_cast<double>(d.expected);
    const bool streaming = r.subscribers + r.shm_readers > 0;
    return fmt::format(
        "{:>5} {:>5} {:>5} | {:>6} {:>9} {:>7} | {:>8} {:>8} {:>8} {:>8} | {:>6.2f} {:>6} {:>6} | "
        "{:>6.2f} {:>6.2f} {:>4} | {:>7.0f} | {}\n",
        r.rate_hz,
        r.shm_readers > 0 ? fmt::format("{}+{}shm", r.subscribers, r.shm_readers)
                          : fmt::format("{}", r.subscribers),
        r.flooders, r.frames_written, d.delivered, streaming ? fmt::format("{:.2f}", miss) : "-",
        streaming ? fmt::format("{:.0f}", r.latency.p50_us) : "-",
        streaming ? fmt::format("{:.0f}", r.latency.p99_us) : "-",
        streaming ? fmt::format("{:.0f}", r.latency.max_us) : "-",
        streaming ? fmt::format("{:.0f}", r.latency.first_p99_us) : "-", r.cpu_percent,
        mib(r.rss_kib), mib(r.hwm_kib), r.keepalive.p99_dev_ms, r.keepalive.max_dev_ms,
        r.keepalive.intervals, r.flood_replies_per_s,
        r.daemon_fifo             ? r.load_start + " (gportd FIFO)"
        : r.realtime_priority > 0 ? r.load_start + " (realtime.priority)"
                                  : r.load_start);
}

nlohmann::json to_json(const CellResult& r) {
    const auto& d = r.delivery;
    return {
        {"rate_hz", r.rate_hz},
        {"subscribers", r.subscribers},
        {"shm_readers", r.shm_readers},
        {"flooders", r.flooders},
        {"seconds", r.seconds},
        {"loadavg_start", r.load_start},
        {"loadavg_end", r.load_end},
        {"frames_written", r.frames_written},
        {"writer_late_frames", r.writer_late},
        {"measuring_threads_sched_fifo", r.realtime},
        {"daemon_sched_fifo", r.daemon_fifo},
        {"realtime_priority", r.realtime_priority},
        {"lines",
         {{"expected", d.expected},
          {"delivered", d.delivered},
          {"missing", d.missing},
          {"reported_dropped", d.reported_dropped},
          {"out_of_order", d.out_of_order},
          {"subscribers_closed", d.subscribers_closed}}},
        {"latency_us",
         {{"samples", r.latency.samples},
          {"p50", r.latency.p50_us},
          {"p99", r.latency.p99_us},
          {"p999", r.latency.p999_us},
          {"max", r.latency.max_us},
          {"first_subscriber_p50", r.latency.first_p50_us},
          {"first_subscriber_p99", r.latency.first_p99_us}}},
        {"keepalive_deviation_ms",
         {{"intervals", r.keepalive.intervals},
          {"p50", r.keepalive.p50_dev_ms},
          {"p99", r.keepalive.p99_dev_ms},
          {"max", r.keepalive.max_dev_ms}}},
        {"daemon",
         {{"cpu_percent_of_one_core", r.cpu_percent},
          {"system_cpu_percent_of_one_core", r.system_percent},
          {"vm_rss_kib", r.rss_kib},
          {"vm_hwm_kib", r.hwm_kib},
          {"exit_status", r.daemon_exit},
          {"counters", r.daemon_counters}}},
        {"flood_replies_per_s", r.flood_replies_per_s},
        {"stops", to_json(r.stops)},
    };
}

}  // namespace gport::bench
