// Typed MAVLink messages: the gimbal protocol v2 subset gport-mavlink speaks.
//
//   id   name                               base  full  CRC_EXTRA
//   0    HEARTBEAT                             9     9     50
//   76   COMMAND_LONG                         33    33    152
//   77   COMMAND_ACK                           3    10    143
//   283  GIMBAL_DEVICE_INFORMATION           144   149     74
//   284  GIMBAL_DEVICE_SET_ATTITUDE           32    32     99
//   285  GIMBAL_DEVICE_ATTITUDE_STATUS        40    49    137
//   286  AUTOPILOT_STATE_FOR_GIMBAL_DEVICE    53    57    210
//   (and the camera's and the vehicle position's: camera_message_types.hpp)
//
// (base: the fields before <extensions/>; full: with them.) Each struct
// carries its table (kFields, in wire order) and visits its members in the
// same order; the static_asserts of messages.hpp prove, per message, that the table
// is sorted as MAVLink sorts it, that the CRC_EXTRA computed from it equals
// the published one, and that the members match the table's types.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>
#include <variant>

#include "gport/mavlink/attitude.hpp"
#include "gport/mavlink/fields.hpp"

namespace gport::mavlink {

template <std::size_t N>
using Chars = std::array<char, N>;  // NUL-padded, not necessarily NUL-terminated

// Calls v on each member in turn: the body of every message's visit().
template <typename V, typename... T>
constexpr void each(V& v, T&... members) {
    (v(members), ...);
}

}  // namespace gport::mavlink

#include "gport/mavlink/camera_message_types.hpp"  // IWYU pragma: export

namespace gport::mavlink {

struct Heartbeat {
    using F = FieldType;
    static constexpr std::uint32_t kId = 0;
    static constexpr std::string_view kName = "HEARTBEAT";
    static constexpr std::uint8_t kCrcExtra = 50;
    static constexpr std::array<FieldSpec, 6> kFields{{
        {F::kU32, "custom_mode"},
        {F::kU8, "type"},
        {F::kU8, "autopilot"},
        {F::kU8, "base_mode"},
        {F::kU8, "system_status"},
        {F::kU8, "mavlink_version"},
    }};
    std::uint32_t custom_mode = 0;
    std::uint8_t type = 0;
    std::uint8_t autopilot = 0;
    std::uint8_t base_mode = 0;
    std::uint8_t system_status = 0;
    std::uint8_t mavlink_version = 3;

    template <typename M, typename V>
    static constexpr void visit(M& m, V&& v) {
        each(v, m.custom_mode, m.type, m.autopilot, m.base_mode, m.system_status,
             m.mavlink_version);
    }
};

struct CommandLong {
    using F = FieldType;
    static constexpr std::uint32_t kId = 76;
    static constexpr std::string_view kName = "COMMAND_LONG";
    static constexpr std::uint8_t kCrcExtra = 152;
    static constexpr std::array<FieldSpec, 11> kFields{{
        {F::kF32, "param1"},
        {F::kF32, "param2"},
        {F::kF32, "param3"},
        {F::kF32, "param4"},
        {F::kF32, "param5"},
        {F::kF32, "param6"},
        {F::kF32, "param7"},
        {F::kU16, "command"},
        {F::kU8, "target_system"},
        {F::kU8, "target_component"},
        {F::kU8, "confirmation"},
    }};
    std::array<float, 7> param{};  // param1..param7
    std::uint16_t command = 0;
    std::uint8_t target_system = 0;
    std::uint8_t target_component = 0;
    std::uint8_t confirmation = 0;

    template <typename M, typename V>
    static constexpr void visit(M& m, V&& v) {
        each(v, m.param[0], m.param[1], m.param[2], m.param[3], m.param[4], m.param[5], m.param[6],
             m.command, m.target_system, m.target_component, m.confirmation);
    }
};

struct CommandAck {
    using F = FieldType;
    static constexpr std::uint32_t kId = 77;
    static constexpr std::string_view kName = "COMMAND_ACK";
    static constexpr std::uint8_t kCrcExtra = 143;
    static constexpr std::array<FieldSpec, 6> kFields{{
        {F::kU16, "command"},
        {F::kU8, "result"},
        {F::kU8, "progress", 0, true},
        {F::kI32, "result_param2", 0, true},
        {F::kU8, "target_system", 0, true},
        {F::kU8, "target_component", 0, true},
    }};
    std::uint16_t command = 0;
    std::uint8_t result = 0;
    std::uint8_t progress = 0;
    std::int32_t result_param2 = 0;
    std::uint8_t target_system = 0;
    std::uint8_t target_component = 0;

    template <typename M, typename V>
    static constexpr void visit(M& m, V&& v) {
        each(v, m.command, m.result, m.progress, m.result_param2, m.target_system,
             m.target_component);
    }
};

struct GimbalDeviceInformation {
    using F = FieldType;
    static constexpr std::uint32_t kId = 283;
    static constexpr std::string_view kName = "GIMBAL_DEVICE_INFORMATION";
    static constexpr std::uint8_t kCrcExtra = 74;
    static constexpr std::array<FieldSpec, 17> kFields{{
        {F::kU64, "uid"},
        {F::kU32, "time_boot_ms"},
        {F::kU32, "firmware_version"},
        {F::kU32, "hardware_version"},
        {F::kF32, "roll_min"},
        {F::kF32, "roll_max"},
        {F::kF32, "pitch_min"},
        {F::kF32, "pitch_max"},
        {F::kF32, "yaw_min"},
        {F::kF32, "yaw_max"},
        {F::kU16, "cap_flags"},
        {F::kU16, "custom_cap_flags"},
        {F::kChar, "vendor_name", 32},
        {F::kChar, "model_name", 32},
        {F::kChar, "custom_name", 32},
        {F::kU8, "gimbal_device_id", 0, true},
        {F::kU32, "cap_flags2", 0, true},
    }};
    std::uint64_t uid = 0;
    std::uint32_t time_boot_ms = 0;
    std::uint32_t firmware_version = 0;
    std::uint32_t hardware_version = 0;
    float roll_min = 0, roll_max = 0, pitch_min = 0, pitch_max = 0, yaw_min = 0, yaw_max = 0;
    std::uint16_t cap_flags = 0;
    std::uint16_t custom_cap_flags = 0;
    Chars<32> vendor_name{};
    Chars<32> model_name{};
    Chars<32> custom_name{};
    std::uint8_t gimbal_device_id = 0;
    std::uint32_t cap_flags2 = 0;

    template <typename M, typename V>
    static constexpr void visit(M& m, V&& v) {
        each(v, m.uid, m.time_boot_ms, m.firmware_version, m.hardware_version, m.roll_min,
             m.roll_max, m.pitch_min, m.pitch_max, m.yaw_min, m.yaw_max, m.cap_flags,
             m.custom_cap_flags, m.vendor_name, m.model_name, m.custom_name, m.gimbal_device_id,
             m.cap_flags2);
    }
};

struct GimbalDeviceSetAttitude {
    using F = FieldType;
    static constexpr std::uint32_t kId = 284;
    static constexpr std::string_view kName = "GIMBAL_DEVICE_SET_ATTITUDE";
    static constexpr std::uint8_t kCrcExtra = 99;
    static constexpr std::array<FieldSpec, 7> kFields{{
        {F::kF32, "q", 4},
        {F::kF32, "angular_velocity_x"},
        {F::kF32, "angular_velocity_y"},
        {F::kF32, "angular_velocity_z"},
        {F::kU16, "flags"},
        {F::kU8, "target_system"},
        {F::kU8, "target_component"},
    }};
    Quaternion q{};  // w, x, y, z
    float angular_velocity_x = 0;
    float angular_velocity_y = 0;
    float angular_velocity_z = 0;
    std::uint16_t flags = 0;
    std::uint8_t target_system = 0;
    std::uint8_t target_component = 0;

    template <typename M, typename V>
    static constexpr void visit(M& m, V&& v) {
        each(v, m.q, m.angular_velocity_x, m.angular_velocity_y, m.angular_velocity_z, m.flags,
             m.target_system, m.target_component);
    }
};

struct GimbalDeviceAttitudeStatus {
    using F = FieldType;
    static constexpr std::uint32_t kId = 285;
    static constexpr std::string_view kName = "GIMBAL_DEVICE_ATTITUDE_STATUS";
    static constexpr std::uint8_t kCrcExtra = 137;
    static constexpr std::array<FieldSpec, 12> kFields{{
        {F::kU32, "time_boot_ms"},
        {F::kF32, "q", 4},
        {F::kF32, "angular_velocity_x"},
        {F::kF32, "angular_velocity_y"},
        {F::kF32, "angular_velocity_z"},
        {F::kU32, "failure_flags"},
        {F::kU16, "flags"},
        {F::kU8, "target_system"},
        {F::kU8, "target_component"},
        {F::kF32, "delta_yaw", 0, true},
        {F::kF32, "delta_yaw_velocity", 0, true},
        {F::kU8, "gimbal_device_id", 0, true},
    }};
    std::uint32_t time_boot_ms = 0;
    Quaternion q{};  // w, x, y, z
    float angular_velocity_x = 0;
    float angular_velocity_y = 0;
    float angular_velocity_z = 0;
    std::uint32_t failure_flags = 0;
    std::uint16_t flags = 0;
    std::uint8_t target_system = 0;
    std::uint8_t target_component = 0;
    float delta_yaw = 0;
    float delta_yaw_velocity = 0;
    std::uint8_t gimbal_device_id = 0;

    template <typename M, typename V>
    static constexpr void visit(M& m, V&& v) {
        each(v, m.time_boot_ms, m.q, m.angular_velocity_x, m.angular_velocity_y,
             m.angular_velocity_z, m.failure_flags, m.flags, m.target_system, m.target_component,
             m.delta_yaw, m.delta_yaw_velocity, m.gimbal_device_id);
    }
};

struct AutopilotStateForGimbalDevice {
    using F = FieldType;
    static constexpr std::uint32_t kId = 286;
    static constexpr std::string_view kName = "AUTOPILOT_STATE_FOR_GIMBAL_DEVICE";
    static constexpr std::uint8_t kCrcExtra = 210;
    static constexpr std::array<FieldSpec, 13> kFields{{
        {F::kU64, "time_boot_us"},
        {F::kF32, "q", 4},
        {F::kU32, "q_estimated_delay_us"},
        {F::kF32, "vx"},
        {F::kF32, "vy"},
        {F::kF32, "vz"},
        {F::kU32, "v_estimated_delay_us"},
        {F::kF32, "feed_forward_angular_velocity_z"},
        {F::kU16, "estimator_status"},
        {F::kU8, "target_system"},
        {F::kU8, "target_component"},
        {F::kU8, "landed_state"},
        {F::kF32, "angular_velocity_z", 0, true},
    }};
    std::uint64_t time_boot_us = 0;
    Quaternion q{};  // w, x, y, z
    std::uint32_t q_estimated_delay_us = 0;
    float vx = 0, vy = 0, vz = 0;
    std::uint32_t v_estimated_delay_us = 0;
    float feed_forward_angular_velocity_z = 0;
    std::uint16_t estimator_status = 0;
    std::uint8_t target_system = 0;
    std::uint8_t target_component = 0;
    std::uint8_t landed_state = 0;
    float angular_velocity_z = 0;

    template <typename M, typename V>
    static constexpr void visit(M& m, V&& v) {
        each(v, m.time_boot_us, m.q, m.q_estimated_delay_us, m.vx, m.vy, m.vz,
             m.v_estimated_delay_us, m.feed_forward_angular_velocity_z, m.estimator_status,
             m.target_system, m.target_component, m.landed_state, m.angular_velocity_z);
    }
};

using Message =
    std::variant<Heartbeat, CommandLong, CommandAck, GimbalDeviceInformation,
                 GimbalDeviceSetAttitude, GimbalDeviceAttitudeStatus, AutopilotStateForGimbalDevice,
                 Attitude, GlobalPositionInt, CameraInformation, CameraSettings, StorageInformation,
                 CameraCaptureStatus, CameraImageCaptured, SystemTime, GpsRawInt>;

}  // namespace gport::mavlink
