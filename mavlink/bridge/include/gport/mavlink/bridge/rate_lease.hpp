// The lease of a rate command sent to gportd as `speed` (docs/mavlink.md,
// "The lease of a rate"): long enough to reach the commander's next
// message, short enough that a silent commander stops the gimbal soon.
//
//   lease = clamp(1.5 × the longest of the last 4 intervals between the
//                 gimbal manager's GIMBAL_DEVICE_SET_ATTITUDE messages,
//                 --lease-ms, the ceiling)
//
// Every message counts, whatever it carries (angles, rates, PX4's all-NaN
// idle stream): a manager streams them all at its link's pace, so the
// first rate of a slow link already gets that link's lease (PX4's Onboard
// link: about 1.7 s apart; counting rate messages only gave the first one
// --lease-ms and a stop before the next, issue 31). An interval longer
// than the ceiling is a new stream, not a slow one, and is not counted.
// The ceiling is kDefaultCeiling until gportd says its
// keepalive.max_duration_ms is lower (its -32602 names it). Pure: the
// caller gives the time.
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <optional>
#include <string_view>

#include "gport/client/types.hpp"

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

    // A GIMBAL_DEVICE_SET_ATTITUDE of the manager arrived at `now` (any
    // kind): the lease for a rate it carries.
    ms on_message(Clock::time_point now);
    // The lease on_message last returned (floor before any).
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

// What goes with a rate to gportd's `speed`: the lease as its lease_ms and
// its duration_ms. Without a duration gportd ends the speed after its
// keepalive.default_duration_ms (1 s by default) whatever the lease: a
// slow link's rate stopped 1 s into each 1.7 s interval (PX4's Onboard
// link, issue 31). Each rate message renews both.
client::SpeedOptions speed_options(std::chrono::milliseconds lease);

// The N of gportd's "lease_ms must be an integer from 1 to N
// (keepalive.max_duration_ms)" or "duration_ms must be ..." (both are
// bounded by it), or none for another message.
std::optional<std::chrono::milliseconds> max_lease_in(std::string_view gportd_message);

}  // namespace gport::mavlink::bridge
