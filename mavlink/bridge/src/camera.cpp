#include "gport/mavlink/bridge/camera.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "gport/mavlink/attitude.hpp"
#include "gport/mavlink/enums.hpp"
#include "gport/mavlink/messages.hpp"

namespace gport::mavlink::bridge {

namespace {

constexpr float kUnknown = std::numeric_limits<float>::quiet_NaN();

template <std::size_t N>
std::array<std::uint8_t, N> bytes_of(std::string_view text) {
    std::array<std::uint8_t, N> out{};
    for (std::size_t i = 0; i < text.size() && i < N; ++i) {
        out[i] = static_cast<std::uint8_t>(text[i]);
    }
    return out;
}

// CAMERA_INFORMATION ... CAMERA_CAPTURE_STATUS, and CAMERA_IMAGE_CAPTURED
// (a missed one asked again).
bool is_camera_message(std::uint32_t id) {
    return id >= CameraInformation::kId && id <= CameraImageCaptured::kId;
}

}  // namespace

std::optional<std::uint32_t> requested_message(const CommandLong& command) {
    switch (command.command) {
        case mav_cmd::kRequestMessage: {
            const float id = command.param[0];
            if (!(id >= 0 && id <= 0xFFFFFF) || id != std::floor(id)) {
                return std::nullopt;
            }
            return static_cast<std::uint32_t>(id);
        }
        case mav_cmd::kRequestCameraInformation:
            return CameraInformation::kId;
        case mav_cmd::kRequestCameraSettings:
            return CameraSettings::kId;
        case mav_cmd::kRequestStorageInformation:
            return StorageInformation::kId;
        case mav_cmd::kRequestCameraCaptureStatus:
            return CameraCaptureStatus::kId;
        default:
            return std::nullopt;
    }
}

bool is_camera_command(const CommandLong& command) {
    switch (command.command) {
        case mav_cmd::kImageStartCapture:
        case mav_cmd::kImageStopCapture:
        case mav_cmd::kVideoStartCapture:
        case mav_cmd::kVideoStopCapture:
        case mav_cmd::kDoDigicamControl:
        case mav_cmd::kRequestCameraInformation:
        case mav_cmd::kRequestCameraSettings:
        case mav_cmd::kRequestStorageInformation:
        case mav_cmd::kRequestCameraCaptureStatus:
            return true;
        case mav_cmd::kRequestMessage: {
            const auto id = requested_message(command);
            return id && is_camera_message(*id);
        }
        default:
            return false;
    }
}

CameraInformation make_camera_information(std::uint32_t time_boot_ms, std::uint8_t gimbal_compid) {
    CameraInformation info;
    info.time_boot_ms = time_boot_ms;
    info.vendor_name = bytes_of<32>("HEQUAV");
    info.model_name = bytes_of<32>("G-Port");
    info.flags = camera_cap::kCaptureImage | camera_cap::kCaptureVideo;
    // Unknown: NaN for the optics (the standard's "use NaN if not known"),
    // 0 for the resolution, no camera definition file.
    info.focal_length = info.sensor_size_h = info.sensor_size_v = kUnknown;
    info.gimbal_device_id = gimbal_compid;
    info.camera_device_id = 0;  // the camera is this component itself
    return info;
}

CameraSettings make_camera_settings(std::uint32_t time_boot_ms, bool recording) {
    CameraSettings settings;
    settings.time_boot_ms = time_boot_ms;
    settings.mode_id = recording ? camera_mode::kVideo : camera_mode::kImage;
    settings.zoom_level = settings.focus_level = kUnknown;
    return settings;
}

StorageInformation make_storage_information(std::uint32_t time_boot_ms) {
    StorageInformation storage;
    storage.time_boot_ms = time_boot_ms;
    storage.storage_id = 1;
    storage.storage_count = 1;
    storage.status = 0;  // STORAGE_STATUS_EMPTY: not available to us
    storage.total_capacity = storage.used_capacity = storage.available_capacity = 0;
    storage.read_speed = storage.write_speed = 0;
    return storage;
}

CameraCaptureStatus make_capture_status(std::uint32_t time_boot_ms, const CaptureState& state) {
    CameraCaptureStatus status;
    status.time_boot_ms = time_boot_ms;
    const std::uint8_t interval = state.interval_s ? 2 : 0;
    status.image_status = static_cast<std::uint8_t>(interval + (state.photo_in_flight ? 1 : 0));
    status.image_interval = state.interval_s ? static_cast<float>(*state.interval_s) : 0.0F;
    status.video_status = state.recording_for ? 1 : 0;
    status.recording_time_ms =
        state.recording_for ? static_cast<std::uint32_t>(state.recording_for->count()) : 0;
    status.available_capacity = kUnknown;  // unknown (STORAGE_INFORMATION: not available)
    status.image_count = state.image_count;
    return status;
}

std::variant<ImagePlan, std::string> plan_images(const CommandLong& command) {
    const float interval = command.param[1];
    const float count = command.param[2];
    if (!(count >= 0 && count <= 1e6F) || count != std::floor(count)) {
        return fmt::format(
            "IMAGE_START_CAPTURE: total images (param3) = {}; allowed a whole number 0 (until "
            "IMAGE_STOP_CAPTURE) to 1000000",
            count);
    }
    ImagePlan plan;
    plan.count = static_cast<std::uint32_t>(count);
    if (plan.count == 1) {
        return plan;
    }
    if (!(interval >= kMinImageIntervalS && interval <= 3600)) {
        return fmt::format(
            "IMAGE_START_CAPTURE: interval (param2) = {} s for {} images; allowed {} to 3600 s",
            interval, plan.count == 0 ? std::string("unlimited") : std::to_string(plan.count),
            kMinImageIntervalS);
    }
    plan.interval_s = interval;
    return plan;
}

bool digicam_shot(const CommandLong& command) {
    return command.param[4] == 1.0F;
}

Quaternion camera_orientation(const std::optional<client::AttitudeSample>& sample,
                              std::optional<double> vehicle_yaw_deg, const Invert& invert) {
    if (!sample) {
        return {kUnknown, kUnknown, kUnknown, kUnknown};
    }
    const auto angles = apply(invert, {sample->imu.roll, sample->imu.pitch, sample->hall.yaw});
    const double yaw = wrap_degrees(angles.yaw + vehicle_yaw_deg.value_or(0.0));
    return to_quaternion({angles.roll, angles.pitch, yaw});
}

std::optional<client::AttitudeSample> capture_sample(
    const std::optional<client::CaptureAttitude>& logged,
    const std::optional<client::AttitudeSample>& own) {
    if (!logged) {
        return own;
    }
    client::AttitudeSample sample;
    sample.imu = logged->imu;
    sample.hall = logged->hall;
    sample.age_ms = logged->age_ms;
    return sample;
}

CameraImageCaptured make_image_captured(const ImageCapture& capture) {
    CameraImageCaptured m;
    m.time_utc = capture.time_utc_us;
    m.time_boot_ms = capture.time_boot_ms;
    m.image_index = capture.image_index;
    m.capture_result = capture.success ? 1 : 0;
    m.camera_id = 0;  // unused by the standard (0: this component)
    m.q = capture.q;
    if (capture.position) {
        m.lat = capture.position->lat;
        m.lon = capture.position->lon;
        m.alt = capture.position->alt;
        m.relative_alt = capture.position->relative_alt;
    }
    return m;
}

std::string position_meta(const std::optional<GlobalPositionInt>& position) {
    if (!position) {
        return {};
    }
    return fmt::format(R"({{"lat":{:.7f},"lon":{:.7f},"alt_m":{:.3f},"relative_alt_m":{:.3f}}})",
                       position->lat / 1e7, position->lon / 1e7, position->alt / 1e3,
                       position->relative_alt / 1e3);
}

}  // namespace gport::mavlink::bridge
