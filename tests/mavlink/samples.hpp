// One message of each type this codec knows, every field set to a value
// that tells it apart from its neighbours (extensions included), and one
// with trailing zeros that truncation drops. Shared by the unit tests and
// the node-mavlink cross-check tool.
#pragma once

#include <cmath>
#include <limits>
#include <vector>

#include "gport/mavlink/enums.hpp"
#include "gport/mavlink/messages.hpp"

namespace gport::mavlink::testing {

inline constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

inline Heartbeat sample_heartbeat() {
    Heartbeat m;
    m.custom_mode = 0xA1B2C3D4;
    m.type = mav_type::kGimbal;
    m.autopilot = mav_autopilot::kInvalid;
    m.base_mode = 0x51;
    m.system_status = mav_state::kActive;
    m.mavlink_version = 3;
    return m;
}

inline CommandLong sample_command_long() {
    CommandLong m;
    m.param = {283.0F, 1.5F, -2.25F, 1e-3F, -1e6F, 0.0F, kNaN};
    m.command = mav_cmd::kRequestMessage;
    m.target_system = 42;
    m.target_component = mav_comp_id::kGimbal;
    m.confirmation = 2;
    return m;
}

inline CommandAck sample_command_ack() {
    CommandAck m;
    m.command = mav_cmd::kVideoStartCapture;
    m.result = mav_result::kDenied;
    m.progress = 255;
    m.result_param2 = -123456;
    m.target_system = 255;
    m.target_component = 190;
    return m;
}

inline GimbalDeviceInformation sample_information() {
    GimbalDeviceInformation m;
    m.uid = 0x0123456789ABCDEFULL;
    m.time_boot_ms = 123456789;
    m.firmware_version = 0x04030201;
    m.hardware_version = 0x00000102;
    m.roll_min = -0.7853982F;
    m.roll_max = 0.7853982F;
    m.pitch_min = -1.5707964F;
    m.pitch_max = 0.5235988F;
    m.yaw_min = kNaN;
    m.yaw_max = 3.1415927F;
    m.cap_flags = gimbal_cap::kHasNeutral | gimbal_cap::kHasRollAxis | gimbal_cap::kHasPitchAxis |
                  gimbal_cap::kHasYawAxis | gimbal_cap::kHasYawFollow | gimbal_cap::kHasYawLock;
    m.custom_cap_flags = 0xBEEF;
    m.vendor_name = *chars_of<32>("HEQUAV", "vendor_name");
    m.model_name = *chars_of<32>("G-Port", "model_name");
    m.custom_name = *chars_of<32>("exactly thirty-two bytes of name", "custom_name");
    m.gimbal_device_id = 1;
    m.cap_flags2 = 0x00010000;
    return m;
}

inline GimbalDeviceSetAttitude sample_set_attitude() {
    GimbalDeviceSetAttitude m;
    m.q = {0.8923991F, -0.0990458F, -0.2391176F, 0.3696438F};
    m.angular_velocity_x = kNaN;
    m.angular_velocity_y = -0.25F;
    m.angular_velocity_z = 0.5235988F;
    m.flags = gimbal_flags::kYawInVehicleFrame | gimbal_flags::kYawLock;
    m.target_system = 1;
    m.target_component = mav_comp_id::kGimbal;
    return m;
}

inline GimbalDeviceAttitudeStatus sample_attitude_status() {
    GimbalDeviceAttitudeStatus m;
    m.time_boot_ms = 4000000000U;
    m.q = {0.9659258F, 0.0F, -0.258819F, 0.0F};
    m.angular_velocity_x = 0.01F;
    m.angular_velocity_y = kNaN;
    m.angular_velocity_z = -0.02F;
    m.failure_flags = gimbal_error::kCommsError | gimbal_error::kNoManager;
    m.flags = gimbal_flags::kYawInVehicleFrame;
    m.target_system = 0;
    m.target_component = 0;
    m.delta_yaw = 1.25F;
    m.delta_yaw_velocity = kNaN;
    m.gimbal_device_id = 7;
    return m;
}

inline AutopilotStateForGimbalDevice sample_autopilot_state() {
    AutopilotStateForGimbalDevice m;
    m.time_boot_us = 0xFEDCBA9876543210ULL;
    m.q = {0.7071068F, 0.0F, 0.0F, 0.7071068F};
    m.q_estimated_delay_us = 1500;
    m.vx = 1.0F;
    m.vy = -2.0F;
    m.vz = 0.125F;
    m.v_estimated_delay_us = 2500;
    m.feed_forward_angular_velocity_z = -0.75F;
    m.estimator_status = 0x0FFF;
    m.target_system = 3;
    m.target_component = mav_comp_id::kGimbal;
    m.landed_state = 2;
    m.angular_velocity_z = 0.0625F;
    return m;
}

// A heartbeat and an ack whose trailing fields are zero: truncated on the wire.
inline CommandAck sample_truncated_ack() {
    CommandAck m;
    m.command = mav_cmd::kImageStartCapture;
    m.result = mav_result::kAccepted;
    return m;
}

inline std::vector<Message> sample_messages() {
    return {sample_heartbeat(),       sample_command_long(), sample_command_ack(),
            sample_information(),     sample_set_attitude(), sample_attitude_status(),
            sample_autopilot_state(), sample_truncated_ack()};
}

}  // namespace gport::mavlink::testing
