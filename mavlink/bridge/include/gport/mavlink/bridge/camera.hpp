// gport-mavlink's camera component (compid 100, MAVLink camera protocol
// v2): the messages it sends and the commands it takes, as pure functions
// (docs/mavlink.md, "The camera component"). The I/O is the Bridge's
// (bridge_camera.cpp).
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <variant>

#include "gport/client/types.hpp"
#include "gport/mavlink/bridge/mapping.hpp"
#include "gport/mavlink/message_types.hpp"

namespace gport::mavlink::bridge {

// A GLOBAL_POSITION_INT older than this is not used (not in a photo's
// CAMERA_IMAGE_CAPTURED, not in its capture's meta).
inline constexpr std::chrono::milliseconds kPositionMaxAge{1000};

// The shortest interval of IMAGE_START_CAPTURE: one camera call at a time,
// and the G-Port's photo key needs its press and release.
inline constexpr double kMinImageIntervalS = 0.5;

// A command the camera component takes when it is broadcast (target
// component 0): its capture commands, and requests for its messages.
bool is_camera_command(const CommandLong& command);

// The message id a request asks for: REQUEST_MESSAGE's param1, or the
// legacy REQUEST_CAMERA_INFORMATION / _SETTINGS / STORAGE_INFORMATION /
// CAMERA_CAPTURE_STATUS; empty for other commands.
std::optional<std::uint32_t> requested_message(const CommandLong& command);

CameraInformation make_camera_information(std::uint32_t time_boot_ms, std::uint8_t gimbal_compid);
CameraSettings make_camera_settings(std::uint32_t time_boot_ms, bool recording);
// "Not available": the G-Port's card cannot be read over its serial port.
StorageInformation make_storage_information(std::uint32_t time_boot_ms);

struct CaptureState {
    std::optional<double> interval_s{};  // an interval capture is running
    bool photo_in_flight = false;
    std::optional<std::chrono::milliseconds> recording_for{};  // recording (assumed), since
    std::int32_t image_count = 0;
};
CameraCaptureStatus make_capture_status(std::uint32_t time_boot_ms, const CaptureState& state);

// IMAGE_START_CAPTURE: param2 the interval (s), param3 the number of images
// (0: until IMAGE_STOP_CAPTURE). One image, or an interval capture.
struct ImagePlan {
    double interval_s = 0;
    std::uint32_t count = 1;  // 0: until stopped
};
// The plan, or why the parameters are refused (names them and what is allowed).
std::variant<ImagePlan, std::string> plan_images(const CommandLong& command);

// DO_DIGICAM_CONTROL: true when it asks for a shot (param5 = 1).
bool digicam_shot(const CommandLong& command);

// The camera's orientation in the earth frame (docs/mavlink.md): roll and
// pitch are the IMU's (gravity-referenced), yaw the vehicle's yaw plus the
// hall yaw (the yaw joint); without the vehicle's yaw, the hall yaw alone
// (relative to the vehicle's nose). NaN without a sample.
Quaternion camera_orientation(const std::optional<client::AttitudeSample>& sample,
                              std::optional<double> vehicle_yaw_deg, const Invert& invert);

// The sample a photo's orientation is made from: the attitude gportd
// logged with the capture, else (an older gportd, or none logged) `own`,
// the bridge's newest sample.
std::optional<client::AttitudeSample> capture_sample(
    const std::optional<client::CaptureAttitude>& logged,
    const std::optional<client::AttitudeSample>& own);

struct ImageCapture {
    std::uint64_t time_utc_us = 0;
    std::uint32_t time_boot_ms = 0;
    std::int32_t image_index = -1;  // -1 when the photo failed
    bool success = false;
    std::optional<GlobalPositionInt> position{};  // fresh, or none: zeros
    Quaternion q{};
};
CameraImageCaptured make_image_captured(const ImageCapture& capture);

// The capture's `meta` for gportd: the position as compact JSON,
// {"lat":deg,"lon":deg,"alt_m":m,"relative_alt_m":m}; "" without one.
std::string position_meta(const std::optional<GlobalPositionInt>& position);

}  // namespace gport::mavlink::bridge
