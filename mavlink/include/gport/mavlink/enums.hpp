// The MAVLink enumeration values gport-mavlink uses, from minimal.xml and
// common.xml (names as there, without the enum's prefix).
#pragma once

#include <cstdint>

namespace gport::mavlink {

namespace mav_type {
inline constexpr std::uint8_t kGcs = 6;
inline constexpr std::uint8_t kGimbal = 26;
inline constexpr std::uint8_t kCamera = 30;
}  // namespace mav_type

namespace mav_autopilot {
inline constexpr std::uint8_t kInvalid = 8;  // not a flight controller
}  // namespace mav_autopilot

namespace mav_state {
inline constexpr std::uint8_t kStandby = 3;
inline constexpr std::uint8_t kActive = 4;
inline constexpr std::uint8_t kCritical = 5;
}  // namespace mav_state

namespace mav_comp_id {
inline constexpr std::uint8_t kAll = 0;  // broadcast
inline constexpr std::uint8_t kAutopilot1 = 1;
inline constexpr std::uint8_t kCamera = 100;
inline constexpr std::uint8_t kGimbal = 154;
}  // namespace mav_comp_id

namespace mav_cmd {
inline constexpr std::uint16_t kDoDigicamControl = 203;
inline constexpr std::uint16_t kSetMessageInterval = 511;
inline constexpr std::uint16_t kRequestMessage = 512;
inline constexpr std::uint16_t kRequestCameraInformation = 521;  // deprecated: REQUEST_MESSAGE
inline constexpr std::uint16_t kRequestCameraSettings = 522;
inline constexpr std::uint16_t kRequestStorageInformation = 525;
inline constexpr std::uint16_t kRequestCameraCaptureStatus = 527;
inline constexpr std::uint16_t kImageStartCapture = 2000;
inline constexpr std::uint16_t kImageStopCapture = 2001;
inline constexpr std::uint16_t kVideoStartCapture = 2500;
inline constexpr std::uint16_t kVideoStopCapture = 2501;
}  // namespace mav_cmd

namespace mav_result {
inline constexpr std::uint8_t kAccepted = 0;
inline constexpr std::uint8_t kTemporarilyRejected = 1;
inline constexpr std::uint8_t kDenied = 2;
inline constexpr std::uint8_t kUnsupported = 3;
inline constexpr std::uint8_t kFailed = 4;
inline constexpr std::uint8_t kInProgress = 5;
}  // namespace mav_result

// CAMERA_CAP_FLAGS
namespace camera_cap {
inline constexpr std::uint32_t kCaptureVideo = 1U << 0;
inline constexpr std::uint32_t kCaptureImage = 1U << 1;
}  // namespace camera_cap

// CAMERA_MODE
namespace camera_mode {
inline constexpr std::uint8_t kImage = 0;
inline constexpr std::uint8_t kVideo = 1;
}  // namespace camera_mode

// GIMBAL_DEVICE_CAP_FLAGS
namespace gimbal_cap {
inline constexpr std::uint16_t kHasRetract = 1U << 0;
inline constexpr std::uint16_t kHasNeutral = 1U << 1;
inline constexpr std::uint16_t kHasRollAxis = 1U << 2;
inline constexpr std::uint16_t kHasRollFollow = 1U << 3;
inline constexpr std::uint16_t kHasRollLock = 1U << 4;
inline constexpr std::uint16_t kHasPitchAxis = 1U << 5;
inline constexpr std::uint16_t kHasPitchFollow = 1U << 6;
inline constexpr std::uint16_t kHasPitchLock = 1U << 7;
inline constexpr std::uint16_t kHasYawAxis = 1U << 8;
inline constexpr std::uint16_t kHasYawFollow = 1U << 9;
inline constexpr std::uint16_t kHasYawLock = 1U << 10;
inline constexpr std::uint16_t kSupportsInfiniteYaw = 1U << 11;
inline constexpr std::uint16_t kSupportsYawInEarthFrame = 1U << 12;
inline constexpr std::uint16_t kHasRcInputs = 1U << 13;
}  // namespace gimbal_cap

// GIMBAL_DEVICE_FLAGS
namespace gimbal_flags {
inline constexpr std::uint16_t kRetract = 1U << 0;
inline constexpr std::uint16_t kNeutral = 1U << 1;
inline constexpr std::uint16_t kRollLock = 1U << 2;
inline constexpr std::uint16_t kPitchLock = 1U << 3;
inline constexpr std::uint16_t kYawLock = 1U << 4;
inline constexpr std::uint16_t kYawInVehicleFrame = 1U << 5;
inline constexpr std::uint16_t kYawInEarthFrame = 1U << 6;
inline constexpr std::uint16_t kAcceptsYawInEarthFrame = 1U << 7;
inline constexpr std::uint16_t kRcExclusive = 1U << 8;
inline constexpr std::uint16_t kRcMixed = 1U << 9;
}  // namespace gimbal_flags

// GIMBAL_DEVICE_ERROR_FLAGS
namespace gimbal_error {
inline constexpr std::uint32_t kAtRollLimit = 1U << 0;
inline constexpr std::uint32_t kAtPitchLimit = 1U << 1;
inline constexpr std::uint32_t kAtYawLimit = 1U << 2;
inline constexpr std::uint32_t kEncoderError = 1U << 3;
inline constexpr std::uint32_t kPowerError = 1U << 4;
inline constexpr std::uint32_t kMotorError = 1U << 5;
inline constexpr std::uint32_t kSoftwareError = 1U << 6;
inline constexpr std::uint32_t kCommsError = 1U << 7;
inline constexpr std::uint32_t kCalibrationRunning = 1U << 8;
inline constexpr std::uint32_t kNoManager = 1U << 9;
}  // namespace gimbal_error

}  // namespace gport::mavlink
