// The lease of a rate command sent to gportd as `speed` (docs/mavlink.md,
// "The lease of a rate"): long enough to reach the commander's next
// message, short enough that a silent commander stops the gimbal soon.
//
//   lease = clamp(1.5 × the longest of the last 4 intervals between rate
//                 messages, --lease-ms, the ceiling)
//
// An interval longer than the ceiling is a new stream, not a slow one, and
// is not counted. The ceiling is kDefaultCeiling until gportd says its
// keepalive.max_duration_ms is lower (its -32602 names it). Pure: the
// caller gives the time.
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <optional>
#include <string_view>

namespace gport::mavlink::bridge {

class RateLease {
  public:
    using Clock = std::chrono::steady_clock;
    using ms = std::chrono::milliseconds;
    // The longest lease unless gportd allows less: a silent commander's
    // last rate runs for at most this long.
    static constexpr ms kDefaultCeiling{5000};
    static constexpr std::size_t kIntervals = 4;

    explicit RateLease(ms floor) : floor_(floor) {}

    // A rate message arrived at `now`: the lease to send with it.
    ms on_rate(Clock::time_point now);
    // The lease on_rate last returned (floor before any).
    ms current() const;
    // gportd's limit (keepalive.max_duration_ms).
    void set_ceiling(ms ceiling);
    ms ceiling() const { return ceiling_; }

  private:
    ms floor_;
    ms ceiling_ = kDefaultCeiling;
    std::array<Clock::duration, kIntervals> intervals_{};
    std::size_t next_ = 0;
    std::optional<Clock::time_point> last_;
};

// The N of gportd's "lease_ms must be an integer from 1 to N
// (keepalive.max_duration_ms)", or none for another message.
std::optional<std::chrono::milliseconds> max_lease_in(std::string_view gportd_message);

}  // namespace gport::mavlink::bridge
