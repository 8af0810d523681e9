// The gimbal for the line-rate benchmark: gport-sim's simulator, in this
// process on its own thread, draining the line at a real UART's rate
// (SimOptions::baud, docs/simulator.md "The line rate"). Its trace stamps
// each received frame when its last byte arrived at that rate; this class
// turns those stamps into CLOCK_MONOTONIC times and keeps the speed frames.
#pragma once

#include <atomic>
#include <boost/asio/io_context.hpp>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "gport/sim/simulator.hpp"

namespace gport::bench {

class LineSim {
  public:
    // Starts the simulator at `baud`, streaming attitude at `rate_hz`, with
    // a symlink to its slave at `link`.
    LineSim(unsigned baud, double rate_hz, const std::string& link);
    ~LineSim();
    LineSim(const LineSim&) = delete;
    LineSim& operator=(const LineSim&) = delete;

    const std::string& device() const { return device_; }
    // Zero-speed and moving speed frames read so far (any thread).
    std::uint64_t stops_seen() const { return stops_.load(); }
    std::uint64_t speeds_seen() const { return speeds_.load(); }
    // When zero-speed frame `n` (from 0) had fully arrived, CLOCK_MONOTONIC ns;
    // -1 if it has not.
    std::int64_t stop_time(std::uint64_t n) const;
    // The most bytes the simulator found waiting in the pty at once.
    std::uint64_t backlog_max();

  private:
    void on_trace(const std::string& line);

    boost::asio::io_context io_;
    std::int64_t start_ns_ = 0;  // the simulator's t_ms = 0, taken just before it starts
    std::unique_ptr<sim::PtySimulator> sim_;
    std::string device_;
    mutable std::mutex mutex_;
    std::vector<std::int64_t> stop_times_;
    std::atomic<std::uint64_t> stops_{0};
    std::atomic<std::uint64_t> speeds_{0};
    std::thread thread_;
};

}  // namespace gport::bench
