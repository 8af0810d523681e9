// One message of each type this codec knows, every field set to a value
// that tells it apart from its neighbours (extensions included), and one
// with trailing zeros that truncation drops. Shared by the unit tests and
// the node-mavlink cross-check tool.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <string_view>
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

// The camera component's messages and the vehicle state it reads.
inline Attitude sample_vehicle_attitude() {
    Attitude m;
    m.time_boot_ms = 123456;
    m.roll = 0.125F;
    m.pitch = -0.25F;
    m.yaw = 1.5F;
    m.rollspeed = 0.01F;
    m.pitchspeed = -0.02F;
    m.yawspeed = kNaN;
    return m;
}

inline GlobalPositionInt sample_position() {
    GlobalPositionInt m;
    m.time_boot_ms = 654321;
    m.lat = -353632621;
    m.lon = 1491652374;
    m.alt = 584070;
    m.relative_alt = -1250;
    m.vx = -120;
    m.vy = 35;
    m.vz = -7;
    m.hdg = 35999;
    return m;
}

inline SystemTime sample_system_time() {
    SystemTime m;
    m.time_unix_usec = 1795910400123456ULL;
    m.time_boot_ms = 654000;
    return m;
}

inline GpsRawInt sample_gps() {
    GpsRawInt m;
    m.time_usec = 654000000;
    m.fix_type = 6;
    m.lat = -353632621;
    m.lon = 1491652374;
    m.alt = 584070;
    m.eph = 70;
    m.epv = 120;
    m.vel = 1512;
    m.cog = 9001;
    m.satellites_visible = 17;
    m.alt_ellipsoid = 612000;
    m.h_acc = 14;
    m.v_acc = 25;
    m.vel_acc = 30;
    m.hdg_acc = 5000;
    m.yaw = 18000;
    return m;
}

inline CameraInformation sample_camera_information() {
    CameraInformation m;
    m.time_boot_ms = 1000;
    m.firmware_version = 0x01020304;
    m.focal_length = kNaN;
    m.sensor_size_h = 6.17F;
    m.sensor_size_v = 4.55F;
    m.flags = 3;
    m.resolution_h = 4000;
    m.resolution_v = 3000;
    m.cam_definition_version = 7;
    const std::string_view vendor = "HEQUAV", model = "G-Port";
    std::copy(vendor.begin(), vendor.end(), m.vendor_name.begin());
    std::copy(model.begin(), model.end(), m.model_name.begin());
    m.lens_id = 2;
    m.cam_definition_uri = *chars_of<140>("http://example.invalid/camera.xml", "uri");
    m.gimbal_device_id = 154;
    m.camera_device_id = 5;
    return m;
}

inline CameraSettings sample_camera_settings() {
    CameraSettings m;
    m.time_boot_ms = 77;
    m.mode_id = 1;
    m.zoom_level = kNaN;
    m.focus_level = 50.0F;
    m.camera_device_id = 1;
    return m;
}

inline StorageInformation sample_storage() {
    StorageInformation m;
    m.time_boot_ms = 9;
    m.total_capacity = 32000.0F;
    m.used_capacity = 1.5F;
    m.available_capacity = 31998.5F;
    m.read_speed = 90.0F;
    m.write_speed = 45.0F;
    m.storage_id = 1;
    m.storage_count = 1;
    m.status = 2;
    m.type = 3;
    m.name = *chars_of<32>("card", "name");
    m.storage_usage = 1;
    return m;
}

inline CameraCaptureStatus sample_capture_status() {
    CameraCaptureStatus m;
    m.time_boot_ms = 4242;
    m.image_interval = 1.5F;
    m.recording_time_ms = 60000;
    m.available_capacity = kNaN;
    m.image_status = 3;
    m.video_status = 1;
    m.image_count = 17;
    m.camera_device_id = 0;
    return m;
}

inline CameraImageCaptured sample_image_captured() {
    CameraImageCaptured m;
    m.time_utc = 1764000000123456ULL;
    m.time_boot_ms = 31337;
    m.lat = 473977420;
    m.lon = 85455940;
    m.alt = 488000;
    m.relative_alt = 30000;
    m.q = {0.9659258F, 0.0F, -0.2588190F, 0.0F};
    m.image_index = 41;
    m.camera_id = 0;
    m.capture_result = 1;
    m.file_url = *chars_of<205>("", "file_url");
    return m;
}

inline std::vector<Message> sample_messages() {
    return {sample_heartbeat(),
            sample_command_long(),
            sample_command_ack(),
            sample_information(),
            sample_set_attitude(),
            sample_attitude_status(),
            sample_autopilot_state(),
            sample_truncated_ack(),
            sample_vehicle_attitude(),
            sample_position(),
            sample_camera_information(),
            sample_camera_settings(),
            sample_storage(),
            sample_capture_status(),
            sample_image_captured(),
            sample_system_time(),
            sample_gps()};
}

}  // namespace gport::mavlink::testing
