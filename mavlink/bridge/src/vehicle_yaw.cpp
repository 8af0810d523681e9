#include "gport/mavlink/bridge/vehicle_yaw.hpp"

namespace gport::mavlink::bridge {

std::string_view to_string(YawSource source) {
    switch (source) {
        case YawSource::kAutopilotState:
            return "AUTOPILOT_STATE_FOR_GIMBAL_DEVICE";
        case YawSource::kAttitude:
            return "ATTITUDE";
        case YawSource::kNone:
            break;
    }
    return "none";
}

void VehicleYaw::from_autopilot_state(double yaw_deg, std::optional<double> rate_dps,
                                      Clock::time_point now) {
    state_ = Stamped{{yaw_deg, rate_dps, YawSource::kAutopilotState}, now};
}

void VehicleYaw::from_attitude(double yaw_deg, std::optional<double> rate_dps,
                               Clock::time_point now) {
    attitude_ = Stamped{{yaw_deg, rate_dps, YawSource::kAttitude}, now};
}

bool VehicleYaw::fresh(const std::optional<Stamped>& s, Clock::time_point now) {
    return s && now - s->when < kMaxAge;
}

std::optional<VehicleYaw::Reading> VehicleYaw::at(Clock::time_point now) const {
    if (fresh(state_, now)) {
        return state_->reading;
    }
    if (fresh(attitude_, now)) {
        return attitude_->reading;
    }
    return std::nullopt;
}

YawSource VehicleYaw::source(Clock::time_point now) const {
    const auto reading = at(now);
    return reading ? reading->source : YawSource::kNone;
}

}  // namespace gport::mavlink::bridge
