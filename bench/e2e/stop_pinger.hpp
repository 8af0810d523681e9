// The commander of issue 22's measurement (bench_e2e --stop-every MS): a
// client on its own thread (SCHED_FIFO when allowed, like the stop probe)
// that sends `stop` every MS milliseconds and times each round trip, from
// just before the write to the reply read. What a loaded event loop costs
// a commander shows here first.
#pragma once

#include <atomic>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

namespace gport::bench {

struct PingStats {
    std::uint64_t count = 0;  // stops answered
    std::uint64_t lost = 0;   // no reply within 5 s
    double p50_ms = 0;
    double p99_ms = 0;
    double max_ms = 0;
};

class StopPinger {
  public:
    StopPinger(std::string socket, int period_ms);
    ~StopPinger();
    StopPinger(const StopPinger&) = delete;
    StopPinger& operator=(const StopPinger&) = delete;

    void start();
    void stop();  // waits for the round trip in progress
    PingStats stats() const;
    const std::string& error() const { return error_; }

  private:
    void run();

    std::string socket_;
    int period_ms_;
    std::vector<std::int64_t> rtt_ns_;
    std::uint64_t lost_ = 0;
    std::string error_;
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

std::string ping_line(const PingStats& stats, int period_ms);
nlohmann::json to_json(const PingStats& stats);

}  // namespace gport::bench
