// The Bridge's camera component (compid 100): its heartbeat, the requests
// for its messages, photos (single, by interval, DIGICAM shots) and video
// as gportd `photo` / `record` with the vehicle's position as the
// capture's `meta`, and CAMERA_IMAGE_CAPTURED after each photo
// (docs/mavlink.md, "The camera component").
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>

#include "bridge.hpp"
#include "gport/mavlink/enums.hpp"

namespace gport::mavlink::bridge {

// Addressed to the camera: its component id, or broadcast and a camera
// command (a broadcast photo is taken once, by the camera, not by both).
bool Bridge::for_camera(const CommandLong& command) const {
    if (!options_.camera) {
        return false;
    }
    const std::uint8_t us = *trust_.vehicle();
    if (command.target_system != 0 && command.target_system != us) {
        return false;
    }
    return command.target_component == kCameraCompid ||
           (command.target_component == mav_comp_id::kAll && is_camera_command(command));
}

void Bridge::load_image_count() {
    if (auto error = image_count_.load()) {
        spdlog::warn("camera: {}; image_index counts from 0 this run and is not kept",
                     error->message);
    } else if (!image_count_.kept()) {
        spdlog::info(
            "camera: no state directory (--state-dir): image_index counts from 0 each run");
    } else {
        spdlog::info("camera: {} images taken so far ({}): the next has image_index {}",
                     image_count_.count(), image_count_.path(), image_count_.count());
    }
}

void Bridge::send_camera_heartbeat(const Origin& to) {
    Heartbeat hb;
    hb.type = mav_type::kCamera;
    hb.autopilot = mav_autopilot::kInvalid;
    hb.system_status = system_status(health());
    send(hb, to, kCameraCompid);
}

void Bridge::on_camera_command(const Requester& from, const CommandLong& command) {
    switch (command.command) {
        case mav_cmd::kRequestMessage:
        case mav_cmd::kRequestCameraInformation:
        case mav_cmd::kRequestCameraSettings:
        case mav_cmd::kRequestStorageInformation:
        case mav_cmd::kRequestCameraCaptureStatus:
            camera_request(from, command);
            break;
        case mav_cmd::kImageStartCapture:
            start_images(from, command);
            break;
        case mav_cmd::kImageStopCapture:
            stop_images();
            ack(from, command.command, mav_result::kAccepted, kCameraCompid);
            break;
        case mav_cmd::kVideoStartCapture:
        case mav_cmd::kVideoStopCapture:
            if (!camera_busy(from, command, kCameraCompid)) {
                camera_record(from, command.command, command.command == mav_cmd::kVideoStartCapture,
                              false);
            }
            break;
        case mav_cmd::kDoDigicamControl:
            if (!digicam_shot(command)) {
                ack(from, command.command, mav_result::kUnsupported, kCameraCompid);
            } else if (!merged_photo(from, command) && !camera_busy(from, command, kCameraCompid)) {
                begin_photo(from, command.command);
            }
            break;
        default:
            ack(from, command.command, mav_result::kUnsupported, kCameraCompid);
            break;
    }
}

void Bridge::camera_request(const Requester& from, const CommandLong& command) {
    const auto id = requested_message(command);
    const auto accept = [&] { ack(from, command.command, mav_result::kAccepted, kCameraCompid); };
    const std::uint32_t now = time_boot_ms();
    if (id == CameraInformation::kId) {
        accept();
        send(make_camera_information(now, options_.compid), from.origin, kCameraCompid);
    } else if (id == CameraSettings::kId) {
        accept();
        send(make_camera_settings(now, recording_since_.has_value()), from.origin, kCameraCompid);
    } else if (id == StorageInformation::kId) {
        accept();
        send(make_storage_information(now), from.origin, kCameraCompid);
    } else if (id == CameraCaptureStatus::kId) {
        accept();
        send(capture_status(), from.origin, kCameraCompid);
    } else if (id == Heartbeat::kId) {
        accept();
        send_camera_heartbeat(from.origin);
    } else {
        ack(from, command.command, mav_result::kDenied, kCameraCompid);
    }
}

CameraCaptureStatus Bridge::capture_status() const {
    CaptureState state;
    if (images_ && images_->count != 1) {
        state.interval_s = images_->interval_s;
    }
    state.photo_in_flight = photo_in_flight_;
    if (recording_since_) {
        state.recording_for =
            std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - *recording_since_);
    }
    state.image_count = image_count_.count();
    return make_capture_status(time_boot_ms(), state);
}

bool Bridge::camera_busy(const Requester& from, const CommandLong& command, std::uint8_t compid) {
    if (connected_ && !camera_in_flight_) {
        return false;
    }
    if (camera_in_flight_) {
        log_.warn("camera command rejected: another in flight", [&] {
            return fmt::format(
                "mavlink: camera command {} from system {} component {} answered "
                "TEMPORARILY_REJECTED: the previous camera command is still with gportd (one "
                "at a time)",
                command.command, from.header.sysid, from.header.compid);
        });
    }
    ack(from, command.command, mav_result::kTemporarilyRejected, compid);
    return true;
}

void Bridge::start_images(const Requester& from, const CommandLong& command) {
    auto plan = plan_images(command);
    if (const auto* why = std::get_if<std::string>(&plan)) {
        log_.warn("IMAGE_START_CAPTURE refused", "mavlink: " + *why);
        ack(from, command.command, mav_result::kDenied, kCameraCompid);
        return;
    }
    const auto& images = std::get<ImagePlan>(plan);
    if (images.count == 1 && merged_photo(from, command)) {
        return;
    }
    if (images_) {
        log_.warn("IMAGE_START_CAPTURE refused: interval running",
                  "mavlink: IMAGE_START_CAPTURE answered TEMPORARILY_REJECTED: an interval "
                  "capture is running (IMAGE_STOP_CAPTURE ends it)");
        ack(from, command.command, mav_result::kTemporarilyRejected, kCameraCompid);
        return;
    }
    if (camera_busy(from, command, kCameraCompid)) {
        return;
    }
    if (images.count == 1) {
        begin_photo(from, command.command);
        return;
    }
    spdlog::info("camera: interval capture, {} every {} s",
                 images.count == 0 ? std::string("images until IMAGE_STOP_CAPTURE")
                                   : fmt::format("{} images", images.count),
                 images.interval_s);
    images_ = images;
    images_taken_ = 0;
    ack(from, command.command, mav_result::kAccepted, kCameraCompid);
    image_timer_.expires_after(std::chrono::seconds(0));
    image_tick();
}

void Bridge::image_tick() {
    if (!images_) {
        return;
    }
    if (connected_ && !camera_in_flight_) {
        take_photo(std::nullopt, mav_cmd::kImageStartCapture);
        ++images_taken_;
        if (images_->count != 0 && images_taken_ >= images_->count) {
            spdlog::info("camera: interval capture done ({} images)", images_taken_);
            images_.reset();
            return;
        }
    } else {
        log_.warn("interval photo skipped",
                  connected_ ? "camera: an interval photo skipped: the previous camera call is "
                               "still with gportd"
                             : "camera: an interval photo skipped: gportd is not connected");
    }
    // Scheduled from the previous expiry: the interval does not drift.
    const auto period = std::chrono::duration_cast<Clock::duration>(
        std::chrono::duration<double>(images_->interval_s));
    const auto now = Clock::now();
    const auto next = image_timer_.expiry() + period;
    image_timer_.expires_at(next > now ? next : now + period);
    image_timer_.async_wait([this](boost::system::error_code ec) {
        if (!ec) {
            image_tick();
        }
    });
}

void Bridge::stop_images() {
    if (images_) {
        spdlog::info("camera: interval capture stopped after {} images", images_taken_);
    }
    images_.reset();
    image_timer_.cancel();
}

// record on/off with the position as meta; forced once when gportd does not
// know the recording state (as record() for the gimbal's component).
void Bridge::camera_record(const Requester& from, std::uint16_t command, bool on, bool force) {
    camera_in_flight_ = true;
    gportd_.async_record(
        on, force, capture_options(),
        [this, from, command, on, force](std::optional<client::Error> e, client::RecordResult) {
            if (e && !force && e->is(client::ErrorCode::kInvalidParams)) {
                spdlog::info("record {}: the recording state is unknown; forcing it",
                             on ? "on" : "off");
                camera_record(from, command, on, true);
                return;
            }
            camera_in_flight_ = false;
            if (e) {
                log_.warn("gportd refused record", fmt::format("gportd refused record {}: {}",
                                                               on ? "on" : "off", e->message()));
            } else if (on && !recording_since_) {
                recording_since_ = Clock::now();
            } else if (!on) {
                recording_since_.reset();
            }
            ack(from, command, e ? mav_result::kDenied : mav_result::kAccepted, kCameraCompid);
            send(capture_status(), from.origin, kCameraCompid);
        });
}

}  // namespace gport::mavlink::bridge
