#include "gport/mavlink/bridge/mapping.hpp"

#include <cmath>
#include <limits>
#include <tuple>
#include <utility>

#include "gport/mavlink/attitude.hpp"
#include "gport/mavlink/enums.hpp"
#include "gport/mavlink/messages.hpp"

namespace gport::mavlink::bridge {

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

double flip(bool invert, double value) {
    return invert ? -value : value;
}

double rate_dps(float radians_per_second) {
    return std::isnan(radians_per_second) ? 0.0 : to_degrees(radians_per_second);
}

float to_rad_s(double degrees_per_second) {
    return static_cast<float>(to_radians(degrees_per_second));
}

bool any_rate(const GimbalDeviceSetAttitude& message) {
    return std::isfinite(message.angular_velocity_x) || std::isfinite(message.angular_velocity_y) ||
           std::isfinite(message.angular_velocity_z);
}

SpeedCommand speed_of(const GimbalDeviceSetAttitude& message, const Invert& invert) {
    return {
        apply(invert, {rate_dps(message.angular_velocity_x), rate_dps(message.angular_velocity_y),
                       rate_dps(message.angular_velocity_z)})};
}

}  // namespace

client::Axes apply(const Invert& invert, const client::Axes& axes) {
    return {flip(invert.roll, axes.roll), flip(invert.pitch, axes.pitch),
            flip(invert.yaw, axes.yaw)};
}

bool is_identity(const Quaternion& q) {
    return std::abs(q[0]) == 1.0F && q[1] == 0.0F && q[2] == 0.0F && q[3] == 0.0F;
}

bool rates_win(const GimbalDeviceSetAttitude& message) {
    return is_identity(message.q) && any_rate(message);
}

bool yaw_in_earth_frame(std::uint16_t flags) {
    if ((flags & gimbal_flags::kYawInEarthFrame) != 0) {
        return true;
    }
    const bool frame_given = (flags & gimbal_flags::kYawInVehicleFrame) != 0;
    return !frame_given && (flags & gimbal_flags::kYawLock) != 0;
}

Command map_set_attitude(const GimbalDeviceSetAttitude& message, const Invert& invert,
                         std::optional<double> vehicle_yaw_deg) {
    if ((message.flags & (gimbal_flags::kRetract | gimbal_flags::kNeutral)) != 0) {
        return CenterCommand{};
    }
    if (rates_win(message)) {
        return speed_of(message, invert);
    }
    if (!is_nan(message.q)) {
        const auto euler = to_euler(message.q, "q");
        if (!euler) {
            return NoCommand{"bad quaternion", euler.error().message};
        }
        double yaw = euler->yaw;
        if (yaw_in_earth_frame(message.flags)) {
            if (!vehicle_yaw_deg) {
                return NoCommand{"earth-frame yaw without the vehicle's yaw",
                                 "an earth-frame yaw target needs the vehicle's yaw, and no "
                                 "AUTOPILOT_STATE_FOR_GIMBAL_DEVICE nor ATTITUDE from the "
                                 "vehicle's autopilot in the last second"};
            }
            yaw = wrap_degrees(yaw - *vehicle_yaw_deg);
        }
        return AngleCommand{apply(invert, {euler->roll, euler->pitch, yaw})};
    }
    if (!any_rate(message)) {
        return IdleCommand{};
    }
    return speed_of(message, invert);
}

bool AngleFilter::pass(const client::Axes& target) {
    if (last_ && std::abs(target.roll - last_->roll) <= threshold_ &&
        std::abs(target.pitch - last_->pitch) <= threshold_ &&
        std::abs(target.yaw - last_->yaw) <= threshold_) {
        return false;
    }
    last_ = target;
    return true;
}

bool addressed_to(std::uint8_t target_system, std::uint8_t target_component, std::uint8_t sysid,
                  std::uint8_t compid) {
    return (target_system == 0 || target_system == sysid) &&
           (target_component == mav_comp_id::kAll || target_component == compid);
}

std::uint8_t system_status(const Health& health) {
    return health.gportd_connected && health.link_state == "up" ? mav_state::kActive
                                                                : mav_state::kCritical;
}

std::uint32_t failure_flags(const Health& health) {
    std::uint32_t flags = 0;
    if (!health.gportd_connected) {
        flags |= gimbal_error::kCommsError | gimbal_error::kSoftwareError;
    } else if (health.link_state != "up") {
        flags |= gimbal_error::kCommsError;
    }
    if (!health.manager_seen) {
        flags |= gimbal_error::kNoManager;
    }
    return flags;
}

GimbalDeviceAttitudeStatus make_attitude_status(const AttitudeInputs& inputs, const Health& health,
                                                const Invert& invert) {
    GimbalDeviceAttitudeStatus status;
    status.time_boot_ms = inputs.time_boot_ms;
    status.target_system = inputs.target_system;
    status.target_component = inputs.target_component;
    status.failure_flags = failure_flags(health);
    status.flags = static_cast<std::uint16_t>(inputs.mode_flags | gimbal_flags::kYawInVehicleFrame);
    status.q = {kNaN, kNaN, kNaN, kNaN};
    status.angular_velocity_x = status.angular_velocity_y = status.angular_velocity_z = kNaN;
    if (inputs.sample) {
        const auto& s = *inputs.sample;
        const auto angles = apply(invert, {s.imu.roll, s.imu.pitch, s.hall.yaw});
        status.q = to_quaternion({angles.roll, angles.pitch, angles.yaw});
        if (s.rates) {
            const auto rates = apply(invert, {s.rates->imu.x, s.rates->imu.y, s.rates->hall.yaw});
            status.angular_velocity_x = to_rad_s(rates.roll);
            status.angular_velocity_y = to_rad_s(rates.pitch);
            status.angular_velocity_z = to_rad_s(rates.yaw);
        }
    }
    status.delta_yaw = inputs.vehicle_yaw_deg ? to_rad_s(*inputs.vehicle_yaw_deg) : kNaN;
    status.delta_yaw_velocity =
        inputs.vehicle_yaw_rate_dps ? to_rad_s(*inputs.vehicle_yaw_rate_dps) : kNaN;
    return status;
}

namespace {

constexpr double kNoLimit = 327.67;  // the protocol's whole range: no soft limit

// min and max in radians: gportd's soft limit, else the G-Port's range.
std::pair<float, float> range_of(const std::optional<client::AxisRange>& soft,
                                 const client::AxisRange& mechanical, bool invert) {
    const bool limited = soft && (soft->min > -kNoLimit || soft->max < kNoLimit);
    const client::AxisRange range = limited ? *soft : mechanical;
    const double min = invert ? -range.max : range.min;
    const double max = invert ? -range.min : range.max;
    return {static_cast<float>(to_radians(min)), static_cast<float>(to_radians(max))};
}

}  // namespace

GimbalDeviceInformation make_information(std::uint32_t time_boot_ms,
                                         const std::optional<client::Limits>& limits,
                                         const Invert& invert) {
    GimbalDeviceInformation info;
    info.time_boot_ms = time_boot_ms;
    info.vendor_name = *chars_of<32>("HEQUAV", "vendor_name");
    info.model_name = *chars_of<32>("G-Port", "model_name");
    info.custom_name = *chars_of<32>("gport-mavlink", "custom_name");
    info.cap_flags = gimbal_cap::kHasRetract | gimbal_cap::kHasNeutral | gimbal_cap::kHasRollAxis |
                     gimbal_cap::kHasRollLock | gimbal_cap::kHasPitchAxis |
                     gimbal_cap::kHasPitchLock | gimbal_cap::kHasYawAxis |
                     gimbal_cap::kHasYawFollow | gimbal_cap::kHasYawLock;
    const auto soft = [&](auto member) -> std::optional<client::AxisRange> {
        return limits ? std::optional((*limits).*member) : std::nullopt;
    };
    std::tie(info.roll_min, info.roll_max) =
        range_of(soft(&client::Limits::roll), kGportRange.roll, invert.roll);
    std::tie(info.pitch_min, info.pitch_max) =
        range_of(soft(&client::Limits::pitch), kGportRange.pitch, invert.pitch);
    std::tie(info.yaw_min, info.yaw_max) =
        range_of(soft(&client::Limits::yaw), kGportRange.yaw, invert.yaw);
    return info;
}

}  // namespace gport::mavlink::bridge
