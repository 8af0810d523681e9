// Typed G-Port messages. Data layouts (offsets into the data field, LE):
//
//   cmd   dir   len  layout
//   0x13  down    0  get settings
//   0x14  up     15  settings: [0..10] reserved, [11] dead zone u8,
//                    [12] follow speed u8, [13] inverted i8 (-1 inverted, 1 upright),
//                    [14] reserved
//   0x15  down   15  set settings, same block as 0x14
//   0x16  up      0  settings acknowledged
//   0x85  down   13  control: [0] mode i8 (1 speed, 2 angle, 3 centre, 4 lock),
//                    [1..6] roll/pitch/yaw angle i16 0.01°,
//                    [7..12] roll/pitch/yaw speed i16 0.01°/s
//   0x86  down    1  camera: [0] 1 = toggle recording, 2 = photo
//   0x87  up     12  attitude: imu roll/pitch/yaw, hall roll/pitch/yaw, i16 0.01°
//   0x87  up     24  as above, then hall roll/pitch/yaw rates and imu x/y/z rates,
//                    i16 0.01°/s (field firmware; see docs/protocol.md)
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>
#include <variant>
#include <vector>

#include "gport/contract/limits.hpp"
#include "gport/protocol/frame.hpp"
#include "gport/protocol/result.hpp"

namespace gport::protocol {

enum class Command : std::uint8_t {
    kGetSettings = 0x13,
    kSettings = 0x14,
    kSetSettings = 0x15,
    kSetSettingsAck = 0x16,
    kControl = 0x85,
    kCamera = 0x86,
    kAttitude = 0x87,
};

inline constexpr std::size_t kSettingsSize = 15;
inline constexpr std::size_t kControlSize = 13;
inline constexpr std::size_t kCameraSize = 1;
inline constexpr std::size_t kAttitudeSize = 12;
inline constexpr std::size_t kAttitudeWithRatesSize = 24;

// ---- units -----------------------------------------------------------------

// Largest magnitude an int16 in 0.01 units carries without wrapping; the
// wire's -32768 is refused too, so the range is symmetric. In degrees it is
// the client API's range of angles and speeds (gport/contract/limits.hpp).
inline constexpr std::int16_t kMaxCenti = 32767;
using contract::kMaxDegrees;
static_assert(kMaxCenti / 100.0 == kMaxDegrees, "the API's range is the wire's int16 range");

// Degrees (or °/s) to 0.01 steps, rounded to nearest (halves away from zero).
// Refuses NaN, infinities and values outside ±327.67 with a message naming
// `field` and the allowed range.
Result<std::int16_t> to_centi(double degrees, std::string_view field);
// The same for a value known to be meant (a configured limit, a model's
// position): rounded to nearest, halves away from zero, clamped to ±327.67;
// NaN is 0.
std::int16_t clamped_centi(double degrees);
constexpr double from_centi(std::int16_t centi) {
    return centi / 100.0;
}

// ---- messages ----------------------------------------------------------------

struct GetSettings {
    friend bool operator==(const GetSettings&, const GetSettings&) = default;
};

// The 15-byte settings block of 0x14 and 0x15. Reserved bytes are kept as
// they were received, so a read-modify-write never changes them.
struct SettingsBlock {
    std::array<std::uint8_t, 11> reserved_head{};
    std::uint8_t dead_zone = 0;
    std::uint8_t follow_speed = 0;
    std::int8_t inverted_raw = 1;  // -1 inverted, 1 upright
    std::uint8_t reserved_tail = 0;

    bool inverted() const { return inverted_raw < 0; }
    void set_inverted(bool inverted) { inverted_raw = inverted ? -1 : 1; }
    friend bool operator==(const SettingsBlock&, const SettingsBlock&) = default;
};

struct SettingsReport {  // 0x14
    SettingsBlock block;
    friend bool operator==(const SettingsReport&, const SettingsReport&) = default;
};

struct SetSettings {  // 0x15
    SettingsBlock block;
    friend bool operator==(const SetSettings&, const SetSettings&) = default;
};

struct SetSettingsAck {  // 0x16
    friend bool operator==(const SetSettingsAck&, const SetSettingsAck&) = default;
};

enum class ControlMode : std::int8_t { kSpeed = 1, kAngle = 2, kCenter = 3, kLock = 4 };

// The mode's name, as logs, traces and the client API write it.
constexpr std::string_view to_string(ControlMode mode) {
    switch (mode) {
        case ControlMode::kSpeed:
            return "speed";
        case ControlMode::kAngle:
            return "angle";
        case ControlMode::kCenter:
            return "center";
        case ControlMode::kLock:
            return "lock";
    }
    return "unknown";
}

// A roll/pitch/yaw triple in 0.01 units.
struct Axes {
    std::int16_t roll = 0;
    std::int16_t pitch = 0;
    std::int16_t yaw = 0;
    friend bool operator==(const Axes&, const Axes&) = default;
};

// Converts degrees (or °/s) to Axes, refusing values that do not fit.
Result<Axes> to_axes(double roll, double pitch, double yaw);

// The other way: roll, pitch and yaw in degrees (or °/s). With from_centi,
// the one conversion from the wire's 0.01 units that every attitude shape
// (the notification, the shared-memory ring, the capture log, the replies,
// the journal's lines) is made with.
constexpr std::array<double, 3> degrees_of(const Axes& axes) {
    return {from_centi(axes.roll), from_centi(axes.pitch), from_centi(axes.yaw)};
}

struct Control {  // 0x85
    ControlMode mode = ControlMode::kSpeed;
    Axes angle;
    Axes speed;

    static Control speed_of(Axes speed) { return {ControlMode::kSpeed, {}, speed}; }
    static Control stop() { return speed_of({}); }
    static Control angle_of(Axes angle) { return {ControlMode::kAngle, angle, {}}; }
    static Control center() { return {ControlMode::kCenter, {}, {}}; }
    static Control lock() { return {ControlMode::kLock, {}, {}}; }
    friend bool operator==(const Control&, const Control&) = default;
};

enum class CameraAction : std::int8_t { kToggleRecording = 1, kPhoto = 2 };

struct Camera {  // 0x86
    CameraAction action = CameraAction::kPhoto;
    friend bool operator==(const Camera&, const Camera&) = default;
};

struct AttitudeRates {
    Axes hall;               // hall roll/pitch/yaw rates, 0.01°/s
    std::int16_t imu_x = 0;  // IMU rates, 0.01°/s
    std::int16_t imu_y = 0;
    std::int16_t imu_z = 0;
    friend bool operator==(const AttitudeRates&, const AttitudeRates&) = default;
};

struct Attitude {  // 0x87
    Axes imu;
    Axes hall;
    std::optional<AttitudeRates> rates;  // present in the 24-byte form
    friend bool operator==(const Attitude&, const Attitude&) = default;
};

// A frame whose command this library does not know: kept whole, not an error.
struct RawFrame {
    std::uint8_t command = 0;
    std::vector<std::uint8_t> data;
    friend bool operator==(const RawFrame&, const RawFrame&) = default;
};

using Message = std::variant<GetSettings, SettingsReport, SetSettings, SetSettingsAck, Control,
                             Camera, Attitude, RawFrame>;

// ---- codec -------------------------------------------------------------------

Frame encode(const GetSettings&);
Frame encode(const SettingsReport&);
Frame encode(const SetSettings&);
Frame encode(const SetSettingsAck&);
Frame encode(const Control&);
Frame encode(const Camera&);
Frame encode(const Attitude&);  // 24-byte form when rates are present
Frame encode(const RawFrame&);
Frame encode(const Message&);

// Decodes a frame. Unknown commands become RawFrame; a known command with a
// data length or value it cannot have is an error naming both.
Result<Message> decode(const FrameView& frame);

}  // namespace gport::protocol
