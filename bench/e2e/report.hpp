// What one benchmark cell measured, how it is summarised, and how it is
// printed (a table row) and saved (a JSON object).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "clients.hpp"
#include "fake_gimbal.hpp"
#include "stop_report.hpp"

namespace gport::bench {

struct LatencyStats {
    std::uint64_t samples = 0;
    double p50_us = 0;
    double p99_us = 0;
    double p999_us = 0;
    double max_us = 0;
    // Per frame, the first subscriber's line: the pty, decode and JSON path
    // without the fan-out to the others.
    double first_p50_us = 0;
    double first_p99_us = 0;
};

struct KeepaliveStats {
    std::uint64_t intervals = 0;  // gaps between consecutive keepalive frames
    double p50_dev_ms = 0;        // |gap - period|
    double p99_dev_ms = 0;
    double max_dev_ms = 0;
};

struct DeliveryStats {
    std::uint64_t expected = 0;          // frames written x subscribers
    std::uint64_t delivered = 0;         // attitude lines read with a known counter
    std::uint64_t missing = 0;           // expected - delivered
    std::uint64_t reported_dropped = 0;  // sum of the "dropped" fields the daemon sent
    std::uint64_t out_of_order = 0;
    int subscribers_closed = 0;  // connections the daemon closed during the run
};

struct CellResult {
    double rate_hz = 0;
    int subscribers = 0;
    int shm_readers = 0;  // readers of the shared-memory channel, counted as subscribers
    int flooders = 0;
    double seconds = 0;
    std::string load_start;
    std::string load_end;
    std::uint32_t frames_written = 0;
    std::uint32_t writer_late = 0;
    bool realtime = false;  // the measuring threads ran SCHED_FIFO  // frames our writer sent more
    int realtime_priority = 0;  // --realtime: gportd's realtime.priority
    bool daemon_fifo = false;   // gportd itself ran SCHED_FIFO (--daemon-fifo)
                                // than a period late
    DeliveryStats delivery;
    LatencyStats latency;
    KeepaliveStats keepalive;
    double cpu_percent = 0;     // daemon utime+stime over the stream, % of one core
    double system_percent = 0;  // the stime part of it
    long rss_kib = 0;
    long hwm_kib = 0;
    double flood_replies_per_s = 0;
    StopReport stops;                // --stops: the stop probe's figures
    nlohmann::json daemon_counters;  // the daemon's status counters at the end
    int daemon_exit = -1;            // exit status after SIGTERM
};

DeliveryStats delivery_of(const std::vector<Subscriber>& subscribers, std::uint32_t frames_written);
LatencyStats latency_of(const std::vector<Subscriber>& subscribers,
                        const std::vector<std::int64_t>& write_times);
// Keepalive gaps between speed frames stamped within [from_ns, to_ns]. A gap
// across one of `motion_starts` (sorted) ends at a new motion's first frame
// and is not counted.
KeepaliveStats keepalive_of(const std::vector<ControlStamp>& frames, std::int64_t from_ns,
                            std::int64_t to_ns, double period_ms,
                            const std::vector<std::int64_t>& motion_starts = {});

std::string table_header();
std::string table_row(const CellResult& r);
nlohmann::json to_json(const CellResult& r);

}  // namespace gport::bench
