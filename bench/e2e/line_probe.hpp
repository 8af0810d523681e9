// What the line-rate benchmark measures while a flood runs: a commander that
// starts a motion and stops it, again and again (the delay from `stop`
// written to the whole zero-speed 0x85 read by the gimbal at line rate), and
// an attitude subscriber (the longest gap between its notifications).
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

#include "line_sim.hpp"

namespace gport::bench {

// How long a stop may take before it is called lost (the issue saw 1.34 s).
inline constexpr int kLineStopTimeoutMs = 5000;

class LineStopProbe {
  public:
    // `stops` motions, one every `period_ms` at most.
    LineStopProbe(std::string socket, const LineSim& sim, int stops, int period_ms);
    ~LineStopProbe();
    LineStopProbe(const LineStopProbe&) = delete;
    LineStopProbe& operator=(const LineStopProbe&) = delete;

    void start();
    void join();
    // Stop delays in ms, one per stop that arrived.
    const std::vector<double>& delays_ms() const { return delays_; }
    int lost() const { return lost_; }
    const std::string& error() const { return error_; }

  private:
    void run();
    void cycle(int index);
    std::string call(const std::string& method, const std::string& params);

    std::string socket_;
    const LineSim& sim_;
    int stops_;
    int period_ms_;
    int fd_ = -1;
    std::string pending_;
    std::vector<double> delays_;
    int lost_ = 0;
    std::string error_;
    std::thread thread_;
};

class AttitudeWatch {
  public:
    explicit AttitudeWatch(const std::string& socket);
    ~AttitudeWatch();
    AttitudeWatch(const AttitudeWatch&) = delete;
    AttitudeWatch& operator=(const AttitudeWatch&) = delete;

    // Forgets the gaps so far (the measured window starts now).
    void restart() { restart_ = true; }
    void stop();
    // The longest time between two attitude notifications, in ms; the time
    // since the last one counts too (a stream that stopped).
    double longest_gap_ms() const;
    std::uint64_t lines() const { return lines_.load(); }

  private:
    void run();

    int fd_ = -1;
    std::atomic<bool> running_{true};
    std::atomic<bool> restart_{false};
    std::atomic<std::int64_t> last_ns_{0};
    std::atomic<std::int64_t> longest_ns_{0};
    std::atomic<std::uint64_t> lines_{0};
    std::thread thread_;
};

}  // namespace gport::bench
