// The benchmark plays the gimbal itself on a pseudo-terminal: a writer thread
// sends 0x87 frames at an exact rate, each carrying a counter that the
// subscribers' JSON lines give back, and a reader thread decodes what the
// daemon writes (0x85 keepalives) and stamps every frame.
//
// The counter n travels in the IMU fields: roll = n % 20000, pitch = n / 20000
// (in 0.01°), so a subscriber reads it back as round(roll*100) +
// 20000 * round(pitch*100).
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "posix.hpp"

namespace gport::bench {

inline constexpr std::uint32_t kCounterBase = 20000;

// The counter a subscriber line carries, or 0 when the line has none.
std::uint32_t counter_of_line(std::string_view line);

// One 0x85 frame the daemon sent.
struct ControlStamp {
    std::int64_t t_ns = 0;
    bool speed_nonzero = false;  // a keepalive (or first) speed frame, not a stop
};

class FakeGimbal {
  public:
    // Opens a raw pty pair and starts the reader thread.
    FakeGimbal();
    ~FakeGimbal();
    FakeGimbal(const FakeGimbal&) = delete;
    FakeGimbal& operator=(const FakeGimbal&) = delete;

    const std::string& device() const { return slave_path_; }

    // What frame n's bytes are; by default the 0x87 frame carrying counter n.
    // The comparison with gpsd writes NMEA sentences through the same writer.
    using Payload = std::function<std::string(std::uint32_t)>;
    void set_payload(Payload payload) { payload_ = std::move(payload); }

    // Starts sending frames at `rate_hz`; at most `max_frames` of them.
    void start_stream(double rate_hz, std::size_t max_frames);
    // Stops the writer; afterwards write_times() is stable.
    void stop_stream();
    // write_times()[n] = when frame n's last byte was written (0 = not sent).
    const std::vector<std::int64_t>& write_times() const { return write_times_; }
    std::uint32_t frames_written() const { return written_.load(); }
    // Frames the writer fell behind its schedule by more than one period.
    std::uint32_t late_frames() const { return late_.load(); }
    // Whether the writer (and reader) threads got SCHED_FIFO priority.
    bool realtime() const { return realtime_.load(); }

    // Stops the reader; afterwards control_frames() is stable.
    void stop_reader();
    const std::vector<ControlStamp>& control_frames() const { return control_; }
    // Speed frames read so far, zero (stops) and non-zero: safe from any
    // thread while the reader runs (the stop probe waits on them).
    std::uint64_t stops_seen() const { return stops_seen_.load(); }
    std::uint64_t speeds_seen() const { return speeds_seen_.load(); }

  private:
    void write_loop(double rate_hz, std::size_t max_frames);
    void read_loop();

    Payload payload_;
    Fd master_;
    Fd slave_;  // held open so the line keeps its raw settings and never hangs up
    std::string slave_path_;
    std::vector<std::int64_t> write_times_;
    std::atomic<std::uint32_t> written_{0};
    std::atomic<std::uint32_t> late_{0};
    std::atomic<bool> writing_{false};
    std::atomic<bool> realtime_{false};
    std::atomic<bool> reading_{true};
    std::vector<ControlStamp> control_;
    std::atomic<std::uint64_t> stops_seen_{0};
    std::atomic<std::uint64_t> speeds_seen_{0};
    std::thread writer_;
    std::thread reader_;
};

}  // namespace gport::bench
