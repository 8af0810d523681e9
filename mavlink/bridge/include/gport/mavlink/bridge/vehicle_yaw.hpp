// The vehicle's yaw, which turns an earth-frame yaw target (ROI, YAW_LOCK)
// into the vehicle-frame one the G-Port takes, and gives the camera its
// heading (docs/mavlink.md, "The vehicle's yaw"). Two sources, both from the
// vehicle's autopilot: AUTOPILOT_STATE_FOR_GIMBAL_DEVICE (made for this;
// PX4 sends it only on its Gimbal link) and ATTITUDE (on every link). The
// first is used while fresh, else the second while fresh, else none. Pure:
// the caller gives the time.
#pragma once

#include <chrono>
#include <optional>
#include <string_view>

namespace gport::mavlink::bridge {

enum class YawSource { kNone, kAutopilotState, kAttitude };

// "AUTOPILOT_STATE_FOR_GIMBAL_DEVICE", "ATTITUDE" or "none".
std::string_view to_string(YawSource source);

class VehicleYaw {
  public:
    using Clock = std::chrono::steady_clock;
    // A reading older than this is not used: the vehicle may have turned.
    static constexpr std::chrono::milliseconds kMaxAge{1000};

    struct Reading {
        double yaw_deg = 0;
        std::optional<double> rate_dps{};
        YawSource source = YawSource::kNone;
    };

    void from_autopilot_state(double yaw_deg, std::optional<double> rate_dps,
                              Clock::time_point now);
    void from_attitude(double yaw_deg, std::optional<double> rate_dps, Clock::time_point now);
    // The freshest preferred reading at `now`, or none.
    std::optional<Reading> at(Clock::time_point now) const;
    // The source at(now) uses (kNone without one).
    YawSource source(Clock::time_point now) const;

  private:
    struct Stamped {
        Reading reading;
        Clock::time_point when;
    };
    static bool fresh(const std::optional<Stamped>& s, Clock::time_point now);
    std::optional<Stamped> state_;
    std::optional<Stamped> attitude_;
};

}  // namespace gport::mavlink::bridge
