// Typed MAVLink messages of the camera protocol v2 and the vehicle state the
// camera component reads (common.xml), beside the gimbal's in
// message_types.hpp, which includes this header:
//
//   id   name                    base  full  CRC_EXTRA
//   30   ATTITUDE                  28    28     39
//   33   GLOBAL_POSITION_INT       28    28    104
//   259  CAMERA_INFORMATION       235   237     92
//   260  CAMERA_SETTINGS            5    14    146
//   261  STORAGE_INFORMATION       27    61    179
//   262  CAMERA_CAPTURE_STATUS     18    23     12
//   263  CAMERA_IMAGE_CAPTURED    255   255    133
//
// The tables are checked as the gimbal's are (messages.hpp); the values
// were cross-checked against node-mavlink's classes (tests/mavlink/peer).
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

#include "gport/mavlink/attitude.hpp"
#include "gport/mavlink/fields.hpp"

namespace gport::mavlink {

struct Attitude {
    using F = FieldType;
    static constexpr std::uint32_t kId = 30;
    static constexpr std::string_view kName = "ATTITUDE";
    static constexpr std::uint8_t kCrcExtra = 39;
    static constexpr std::array<FieldSpec, 7> kFields{{
        {F::kU32, "time_boot_ms"},
        {F::kF32, "roll"},
        {F::kF32, "pitch"},
        {F::kF32, "yaw"},
        {F::kF32, "rollspeed"},
        {F::kF32, "pitchspeed"},
        {F::kF32, "yawspeed"},
    }};
    std::uint32_t time_boot_ms = 0;
    float roll = 0, pitch = 0, yaw = 0;  // radians
    float rollspeed = 0, pitchspeed = 0, yawspeed = 0;

    template <typename M, typename V>
    static constexpr void visit(M& m, V&& v) {
        each(v, m.time_boot_ms, m.roll, m.pitch, m.yaw, m.rollspeed, m.pitchspeed, m.yawspeed);
    }
};

struct GlobalPositionInt {
    using F = FieldType;
    static constexpr std::uint32_t kId = 33;
    static constexpr std::string_view kName = "GLOBAL_POSITION_INT";
    static constexpr std::uint8_t kCrcExtra = 104;
    static constexpr std::array<FieldSpec, 9> kFields{{
        {F::kU32, "time_boot_ms"},
        {F::kI32, "lat"},
        {F::kI32, "lon"},
        {F::kI32, "alt"},
        {F::kI32, "relative_alt"},
        {F::kI16, "vx"},
        {F::kI16, "vy"},
        {F::kI16, "vz"},
        {F::kU16, "hdg"},
    }};
    std::uint32_t time_boot_ms = 0;
    std::int32_t lat = 0;           // degE7
    std::int32_t lon = 0;           // degE7
    std::int32_t alt = 0;           // mm, MSL
    std::int32_t relative_alt = 0;  // mm above home
    std::int16_t vx = 0, vy = 0, vz = 0;
    std::uint16_t hdg = 0;

    template <typename M, typename V>
    static constexpr void visit(M& m, V&& v) {
        each(v, m.time_boot_ms, m.lat, m.lon, m.alt, m.relative_alt, m.vx, m.vy, m.vz, m.hdg);
    }
};

// The autopilot's UTC and boot time at one instant (0 while it has no GPS
// time): gportd's capture time (docs/api.md, "The vehicle").
struct SystemTime {
    using F = FieldType;
    static constexpr std::uint32_t kId = 2;
    static constexpr std::string_view kName = "SYSTEM_TIME";
    static constexpr std::uint8_t kCrcExtra = 137;
    static constexpr std::array<FieldSpec, 2> kFields{{
        {F::kU64, "time_unix_usec"},
        {F::kU32, "time_boot_ms"},
    }};
    std::uint64_t time_unix_usec = 0;
    std::uint32_t time_boot_ms = 0;

    template <typename M, typename V>
    static constexpr void visit(M& m, V&& v) {
        each(v, m.time_unix_usec, m.time_boot_ms);
    }
};

// The GPS receiver's fix and its accuracy (h_acc, v_acc: extensions, 0 or
// absent when the autopilot does not know them).
struct GpsRawInt {
    using F = FieldType;
    static constexpr std::uint32_t kId = 24;
    static constexpr std::string_view kName = "GPS_RAW_INT";
    static constexpr std::uint8_t kCrcExtra = 24;
    static constexpr std::array<FieldSpec, 16> kFields{{
        {F::kU64, "time_usec"},
        {F::kI32, "lat"},
        {F::kI32, "lon"},
        {F::kI32, "alt"},
        {F::kU16, "eph"},
        {F::kU16, "epv"},
        {F::kU16, "vel"},
        {F::kU16, "cog"},
        {F::kU8, "fix_type"},
        {F::kU8, "satellites_visible"},
        {F::kI32, "alt_ellipsoid", 0, true},
        {F::kU32, "h_acc", 0, true},  // mm
        {F::kU32, "v_acc", 0, true},  // mm
        {F::kU32, "vel_acc", 0, true},
        {F::kU32, "hdg_acc", 0, true},
        {F::kU16, "yaw", 0, true},
    }};
    std::uint64_t time_usec = 0;
    std::int32_t lat = 0, lon = 0, alt = 0;
    std::uint16_t eph = 0, epv = 0, vel = 0, cog = 0;
    std::uint8_t fix_type = 0;  // GPS_FIX_TYPE
    std::uint8_t satellites_visible = 0;
    std::int32_t alt_ellipsoid = 0;
    std::uint32_t h_acc = 0, v_acc = 0, vel_acc = 0, hdg_acc = 0;
    std::uint16_t yaw = 0;

    template <typename M, typename V>
    static constexpr void visit(M& m, V&& v) {
        each(v, m.time_usec, m.lat, m.lon, m.alt, m.eph, m.epv, m.vel, m.cog, m.fix_type,
             m.satellites_visible, m.alt_ellipsoid, m.h_acc, m.v_acc, m.vel_acc, m.hdg_acc, m.yaw);
    }
};

struct CameraInformation {
    using F = FieldType;
    static constexpr std::uint32_t kId = 259;
    static constexpr std::string_view kName = "CAMERA_INFORMATION";
    static constexpr std::uint8_t kCrcExtra = 92;
    static constexpr std::array<FieldSpec, 15> kFields{{
        {F::kU32, "time_boot_ms"},
        {F::kU32, "firmware_version"},
        {F::kF32, "focal_length"},
        {F::kF32, "sensor_size_h"},
        {F::kF32, "sensor_size_v"},
        {F::kU32, "flags"},
        {F::kU16, "resolution_h"},
        {F::kU16, "resolution_v"},
        {F::kU16, "cam_definition_version"},
        {F::kU8, "vendor_name", 32},
        {F::kU8, "model_name", 32},
        {F::kU8, "lens_id"},
        {F::kChar, "cam_definition_uri", 140},
        {F::kU8, "gimbal_device_id", 0, true},
        {F::kU8, "camera_device_id", 0, true},
    }};
    std::uint32_t time_boot_ms = 0;
    std::uint32_t firmware_version = 0;
    float focal_length = 0, sensor_size_h = 0, sensor_size_v = 0;  // mm; NaN: unknown
    std::uint32_t flags = 0;                                       // CAMERA_CAP_FLAGS
    std::uint16_t resolution_h = 0, resolution_v = 0;              // 0: unknown
    std::uint16_t cam_definition_version = 0;
    std::array<std::uint8_t, 32> vendor_name{};  // uint8_t[32] in the XML: text, NUL-padded
    std::array<std::uint8_t, 32> model_name{};
    std::uint8_t lens_id = 0;
    Chars<140> cam_definition_uri{};
    std::uint8_t gimbal_device_id = 0;
    std::uint8_t camera_device_id = 0;

    template <typename M, typename V>
    static constexpr void visit(M& m, V&& v) {
        each(v, m.time_boot_ms, m.firmware_version, m.focal_length, m.sensor_size_h,
             m.sensor_size_v, m.flags, m.resolution_h, m.resolution_v, m.cam_definition_version,
             m.vendor_name, m.model_name, m.lens_id, m.cam_definition_uri, m.gimbal_device_id,
             m.camera_device_id);
    }
};

struct CameraSettings {
    using F = FieldType;
    static constexpr std::uint32_t kId = 260;
    static constexpr std::string_view kName = "CAMERA_SETTINGS";
    static constexpr std::uint8_t kCrcExtra = 146;
    static constexpr std::array<FieldSpec, 5> kFields{{
        {F::kU32, "time_boot_ms"},
        {F::kU8, "mode_id"},
        {F::kF32, "zoomLevel", 0, true},
        {F::kF32, "focusLevel", 0, true},
        {F::kU8, "camera_device_id", 0, true},
    }};
    std::uint32_t time_boot_ms = 0;
    std::uint8_t mode_id = 0;  // CAMERA_MODE
    float zoom_level = 0;      // NaN: unknown
    float focus_level = 0;
    std::uint8_t camera_device_id = 0;

    template <typename M, typename V>
    static constexpr void visit(M& m, V&& v) {
        each(v, m.time_boot_ms, m.mode_id, m.zoom_level, m.focus_level, m.camera_device_id);
    }
};

struct StorageInformation {
    using F = FieldType;
    static constexpr std::uint32_t kId = 261;
    static constexpr std::string_view kName = "STORAGE_INFORMATION";
    static constexpr std::uint8_t kCrcExtra = 179;
    static constexpr std::array<FieldSpec, 12> kFields{{
        {F::kU32, "time_boot_ms"},
        {F::kF32, "total_capacity"},
        {F::kF32, "used_capacity"},
        {F::kF32, "available_capacity"},
        {F::kF32, "read_speed"},
        {F::kF32, "write_speed"},
        {F::kU8, "storage_id"},
        {F::kU8, "storage_count"},
        {F::kU8, "status"},
        {F::kU8, "type", 0, true},
        {F::kChar, "name", 32, true},
        {F::kU8, "storage_usage", 0, true},
    }};
    std::uint32_t time_boot_ms = 0;
    float total_capacity = 0, used_capacity = 0, available_capacity = 0;  // MiB
    float read_speed = 0, write_speed = 0;                                // MiB/s
    std::uint8_t storage_id = 0;
    std::uint8_t storage_count = 0;
    std::uint8_t status = 0;  // STORAGE_STATUS: 0 EMPTY (missing / not available)
    std::uint8_t type = 0;
    Chars<32> name{};
    std::uint8_t storage_usage = 0;

    template <typename M, typename V>
    static constexpr void visit(M& m, V&& v) {
        each(v, m.time_boot_ms, m.total_capacity, m.used_capacity, m.available_capacity,
             m.read_speed, m.write_speed, m.storage_id, m.storage_count, m.status, m.type, m.name,
             m.storage_usage);
    }
};

struct CameraCaptureStatus {
    using F = FieldType;
    static constexpr std::uint32_t kId = 262;
    static constexpr std::string_view kName = "CAMERA_CAPTURE_STATUS";
    static constexpr std::uint8_t kCrcExtra = 12;
    static constexpr std::array<FieldSpec, 8> kFields{{
        {F::kU32, "time_boot_ms"},
        {F::kF32, "image_interval"},
        {F::kU32, "recording_time_ms"},
        {F::kF32, "available_capacity"},
        {F::kU8, "image_status"},
        {F::kU8, "video_status"},
        {F::kI32, "image_count", 0, true},
        {F::kU8, "camera_device_id", 0, true},
    }};
    std::uint32_t time_boot_ms = 0;
    float image_interval = 0;  // s
    std::uint32_t recording_time_ms = 0;
    float available_capacity = 0;   // MiB
    std::uint8_t image_status = 0;  // 0 idle, 1 capturing, 2 interval idle, 3 interval capturing
    std::uint8_t video_status = 0;  // 0 idle, 1 recording
    std::int32_t image_count = 0;
    std::uint8_t camera_device_id = 0;

    template <typename M, typename V>
    static constexpr void visit(M& m, V&& v) {
        each(v, m.time_boot_ms, m.image_interval, m.recording_time_ms, m.available_capacity,
             m.image_status, m.video_status, m.image_count, m.camera_device_id);
    }
};

struct CameraImageCaptured {
    using F = FieldType;
    static constexpr std::uint32_t kId = 263;
    static constexpr std::string_view kName = "CAMERA_IMAGE_CAPTURED";
    static constexpr std::uint8_t kCrcExtra = 133;
    static constexpr std::array<FieldSpec, 11> kFields{{
        {F::kU64, "time_utc"},
        {F::kU32, "time_boot_ms"},
        {F::kI32, "lat"},
        {F::kI32, "lon"},
        {F::kI32, "alt"},
        {F::kI32, "relative_alt"},
        {F::kF32, "q", 4},
        {F::kI32, "image_index"},
        {F::kU8, "camera_id"},
        {F::kI8, "capture_result"},
        {F::kChar, "file_url", 205},
    }};
    std::uint64_t time_utc = 0;  // µs since 1970
    std::uint32_t time_boot_ms = 0;
    std::int32_t lat = 0, lon = 0;           // degE7
    std::int32_t alt = 0, relative_alt = 0;  // mm
    Quaternion q{};                          // w, x, y, z; earth frame
    std::int32_t image_index = 0;
    std::uint8_t camera_id = 0;
    std::int8_t capture_result = 0;  // 1 success, 0 failure
    Chars<205> file_url{};

    template <typename M, typename V>
    static constexpr void visit(M& m, V&& v) {
        each(v, m.time_utc, m.time_boot_ms, m.lat, m.lon, m.alt, m.relative_alt, m.q, m.image_index,
             m.camera_id, m.capture_result, m.file_url);
    }
};

}  // namespace gport::mavlink
