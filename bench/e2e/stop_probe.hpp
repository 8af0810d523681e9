// The stop probe (bench_e2e --stops N): a commander client on its own thread
// that starts a speed motion again and again and ends each one by one of two
// causes, alternating: it sends `stop`, or it closes its connection while the
// gimbal moves (the deadman, failsafe.on_owner_gone = "stop" by default). It
// stamps each cause right after write() or close() returns; the stop's
// arrival is the first zero-speed 0x85 frame the fake gimbal's reader
// stamped after it. See docs/performance.md, "Stop latency".
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

#include "fake_gimbal.hpp"
#include "posix.hpp"

namespace gport::bench {

enum class StopCause { kStopRequest, kDisconnect };

// One motion ended by the probe.
struct StopSample {
    StopCause cause = StopCause::kStopRequest;
    std::int64_t before_ns = 0;  // just before the write() or close()
    std::int64_t cause_ns = 0;   // right after it returned
    bool seen = false;           // a zero speed reached the pty within kStopTimeoutMs
};

// How long the probe waits for a stop on the wire before calling it lost.
inline constexpr int kStopTimeoutMs = 1000;

// Cycles of one motion each take at least this long (--stops is checked
// against --seconds with it).
inline constexpr double kMinStopCycleMs = 40;

class StopProbe {
  public:
    // `per_cause` motions end by each cause, spread evenly over `seconds`.
    StopProbe(std::string socket, const FakeGimbal& gimbal, int per_cause, double seconds);
    ~StopProbe();
    StopProbe(const StopProbe&) = delete;
    StopProbe& operator=(const StopProbe&) = delete;

    void start();
    // Waits for the last cycle; afterwards the accessors are stable.
    void join();

    const std::vector<StopSample>& samples() const { return samples_; }
    // When each speed command was written: a keepalive gap across one of
    // these is a new motion's first frame, not a keepalive.
    const std::vector<std::int64_t>& motion_starts() const { return motion_starts_; }
    // What went wrong in the probe thread ("" when nothing did).
    const std::string& error() const { return error_; }

  private:
    void run();
    void cycle(int index, std::int64_t start_ns, std::int64_t period_ns);
    void start_motion();
    void end_motion(StopCause cause);

    std::string socket_;
    const FakeGimbal& gimbal_;
    int per_cause_;
    double seconds_;
    Fd fd_;
    std::string pending_;
    std::uint64_t next_id_ = 1;
    std::vector<StopSample> samples_;
    std::vector<std::int64_t> motion_starts_;
    std::string error_;
    std::thread thread_;
};

}  // namespace gport::bench
