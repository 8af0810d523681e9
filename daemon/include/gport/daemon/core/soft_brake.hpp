// Braking at the soft limits during speed motions (docs/api.md, "Braking at
// the soft limits"). An axis moving towards a narrowed side of its range
// (limits.roll/pitch/yaw) is zeroed once its hall angle is within the
// braking distance of that side:
//
//   distance = |speed| × (age + lookahead) + limits.braking_margin_deg
//
// `age` is how old the attitude sample is (the gimbal moved on meanwhile),
// `lookahead` the longest time until the next check (one keepalive period:
// every tick checks, and every sample does in between), and the margin
// covers the zero speed's trip to the gimbal, its deceleration and a late
// timer. The hall angles are used, not the IMU's: they are the joint
// angles, relative to the aircraft, as the limits and angle commands are;
// the IMU attitude turns with the aircraft. Pure: built per check.
#pragma once

#include <string>
#include <vector>

#include "gport/config/config.hpp"
#include "gport/daemon/events.hpp"
#include "gport/protocol/messages.hpp"

namespace gport::daemon {

// A speed after braking, and the axes it zeroed ("roll", "pitch", "yaw" in
// that order).
struct Braked {
    protocol::Axes speed;
    std::vector<std::string> braked;
};

class SoftBrake {
  public:
    SoftBrake(const config::LimitsConfig& limits, Millis lookahead)
        : limits_(limits), lookahead_(lookahead) {}

    // The axes `speed` moves towards a narrowed side of their range: braking
    // them needs a fresh attitude. Empty when nothing is limited that way.
    std::vector<std::string> needs_attitude(protocol::Axes speed) const;
    // `speed` (0.01°/s) with every axis zeroed that moves towards a narrowed
    // side within the braking distance of it (or beyond it), given the hall
    // angles (0.01°) sampled `age` ago.
    Braked apply(protocol::Axes speed, const protocol::Axes& hall, Millis age) const;
    // The braking distance in degrees at `speed_deg_s` for a sample `age` old.
    double distance(double speed_deg_s, Millis age) const;

  private:
    config::LimitsConfig limits_;
    Millis lookahead_;
};

// True when any axis of `speed` is not zero.
bool moves(const protocol::Axes& speed);
// The axes named in `a` or `b`, in roll, pitch, yaw order.
std::vector<std::string> merged(const std::vector<std::string>& a,
                                const std::vector<std::string>& b);

}  // namespace gport::daemon
