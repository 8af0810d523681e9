// The camera component: addressing, its heartbeat, the requests for its
// messages, interval captures and the one-call-at-a-time rule (photos and
// video: camera_photo.cpp).
#include "camera_component.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "gport/mavlink/enums.hpp"

namespace gport::mavlink::bridge {

CameraComponent::CameraComponent(boost::asio::io_context& io, const Options& options, Logbook& log,
                                 CameraHost& host)
    : options_(options),
      log_(log),
      host_(host),
      image_timer_(io),
      image_count_(options.state_dir) {}

bool CameraComponent::addressed(const CommandLong& command) const {
    if (!options_.camera) {
        return false;
    }
    const std::uint8_t us = host_.vehicle_sysid();
    if (command.target_system != 0 && command.target_system != us) {
        return false;
    }
    return command.target_component == kCameraCompid ||
           (command.target_component == mav_comp_id::kAll && is_camera_command(command));
}

void CameraComponent::load_image_count() {
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

void CameraComponent::send(const Message& message, const Origin& to) {
    if (options_.camera) {  // a component that is not announced says nothing
        host_.send_from(kCameraCompid, message, to);
    }
}

void CameraComponent::ack(const Requester& to, std::uint16_t command, std::uint8_t result,
                          std::uint8_t compid) {
    host_.ack_from(compid, to, command, result);
}

void CameraComponent::send_heartbeat(const Origin& to) {
    Heartbeat hb;
    hb.type = mav_type::kCamera;
    hb.autopilot = mav_autopilot::kInvalid;
    hb.system_status = system_status(host_.health());
    send(hb, to);
}

void CameraComponent::on_position(const GlobalPositionInt& position, Clock::time_point when) {
    position_.emplace(position, when);
}

void CameraComponent::on_command(const Requester& from, const CommandLong& command) {
    switch (command.command) {
        case mav_cmd::kRequestMessage:
        case mav_cmd::kRequestCameraInformation:
        case mav_cmd::kRequestCameraSettings:
        case mav_cmd::kRequestStorageInformation:
        case mav_cmd::kRequestCameraCaptureStatus:
            request(from, command);
            break;
        case mav_cmd::kImageStartCapture:
            start_images(from, command);
            break;
        case mav_cmd::kDoDigicamControl:
            if (!digicam_shot(command)) {
                ack(from, command.command, mav_result::kUnsupported);
            } else if (!merged_photo(from, command, kCameraCompid) &&
                       !busy(from, command, kCameraCompid)) {
                begin_photo(from, command.command, kCameraCompid);
            }
            break;
        case mav_cmd::kImageStopCapture:
        case mav_cmd::kVideoStartCapture:
        case mav_cmd::kVideoStopCapture:
            on_gimbal_command(from, command, kCameraCompid);
            break;
        default:
            ack(from, command.command, mav_result::kUnsupported);
            break;
    }
}

void CameraComponent::on_gimbal_command(const Requester& from, const CommandLong& command,
                                        std::uint8_t compid) {
    switch (command.command) {
        case mav_cmd::kImageStartCapture:
            if (!merged_photo(from, command, compid) && !busy(from, command, compid)) {
                begin_photo(from, command.command, compid);
            }
            break;
        case mav_cmd::kImageStopCapture:
            stop_images();
            ack(from, command.command, mav_result::kAccepted, compid);
            break;
        case mav_cmd::kVideoStartCapture:
        case mav_cmd::kVideoStopCapture:
            if (!busy(from, command, compid)) {
                record(from, command.command, compid,
                       command.command == mav_cmd::kVideoStartCapture, false);
            }
            break;
        default:
            ack(from, command.command, mav_result::kUnsupported, compid);
            break;
    }
}

void CameraComponent::request(const Requester& from, const CommandLong& command) {
    const auto id = requested_message(command);
    const auto accept = [&] { ack(from, command.command, mav_result::kAccepted); };
    const std::uint32_t now = host_.time_boot_ms();
    if (id == CameraInformation::kId) {
        accept();
        send(make_camera_information(now, options_.compid), from.origin);
    } else if (id == CameraSettings::kId) {
        accept();
        send(make_camera_settings(now, recording_since_.has_value()), from.origin);
    } else if (id == StorageInformation::kId) {
        accept();
        send(make_storage_information(now), from.origin);
    } else if (id == CameraCaptureStatus::kId) {
        accept();
        send(capture_status(), from.origin);
    } else if (id == Heartbeat::kId) {
        accept();
        send_heartbeat(from.origin);
    } else if (id == CameraImageCaptured::kId && command.command == mav_cmd::kRequestMessage) {
        resend_images(from, command);
    } else {
        ack(from, command.command, mav_result::kDenied);
    }
}

// A missed CAMERA_IMAGE_CAPTURED asked again (image_history.hpp): the kept
// messages as first sent, to the requester. DENIED for a range the camera
// protocol does not define, FAILED when none of it is kept (before this
// run, or older than the newest kImageHistory), TEMPORARILY_REJECTED past
// the re-send budget.
void CameraComponent::resend_images(const Requester& from, const CommandLong& command) {
    const auto range = image_range(command);
    if (!range) {
        ack(from, command.command, mav_result::kDenied);
        return;
    }
    const auto found = image_history_.find(*range, kImageResendBatch);
    if (found.empty()) {
        ack(from, command.command, mav_result::kFailed);
        return;
    }
    if (!resend_budget_.take(Clock::now(), static_cast<double>(found.size()))) {
        log_.warn("camera re-send rejected", [&] {
            return fmt::format(
                "camera: CAMERA_IMAGE_CAPTURED asked again by system {} beyond {} a second: "
                "TEMPORARILY_REJECTED",
                from.header.sysid, kImageResendPerSecond);
        });
        ack(from, command.command, mav_result::kTemporarilyRejected);
        return;
    }
    ack(from, command.command, mav_result::kAccepted);
    for (const auto& message : found) {
        send(message, from.origin);
    }
}

CameraCaptureStatus CameraComponent::capture_status() const {
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
    return make_capture_status(host_.time_boot_ms(), state);
}

// gportd unreachable, or a camera call still with it: answered
// TEMPORARILY_REJECTED from `compid`.
bool CameraComponent::busy(const Requester& from, const CommandLong& command, std::uint8_t compid) {
    if (host_.gportd_connected() && !call_in_flight_) {
        return false;
    }
    if (call_in_flight_) {
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

void CameraComponent::start_images(const Requester& from, const CommandLong& command) {
    auto plan = plan_images(command);
    if (const auto* why = std::get_if<std::string>(&plan)) {
        log_.warn("IMAGE_START_CAPTURE refused", "mavlink: " + *why);
        ack(from, command.command, mav_result::kDenied);
        return;
    }
    const auto& images = std::get<ImagePlan>(plan);
    if (images.count == 1 && merged_photo(from, command, kCameraCompid)) {
        return;
    }
    if (images_) {
        log_.warn("IMAGE_START_CAPTURE refused: interval running",
                  "mavlink: IMAGE_START_CAPTURE answered TEMPORARILY_REJECTED: an interval "
                  "capture is running (IMAGE_STOP_CAPTURE ends it)");
        ack(from, command.command, mav_result::kTemporarilyRejected);
        return;
    }
    if (busy(from, command, kCameraCompid)) {
        return;
    }
    if (images.count == 1) {
        begin_photo(from, command.command, kCameraCompid);
    } else {
        begin_interval(from, command, images);
    }
}

void CameraComponent::begin_interval(const Requester& from, const CommandLong& command,
                                     const ImagePlan& plan) {
    spdlog::info("camera: interval capture, {} every {} s",
                 plan.count == 0 ? std::string("images until IMAGE_STOP_CAPTURE")
                                 : fmt::format("{} images", plan.count),
                 plan.interval_s);
    images_ = plan;
    images_taken_ = 0;
    ack(from, command.command, mav_result::kAccepted);
    image_timer_.expires_after(std::chrono::seconds(0));
    image_tick();
}

void CameraComponent::image_tick() {
    if (!images_) {
        return;
    }
    const bool connected = host_.gportd_connected();
    if (connected && !call_in_flight_) {
        take_photo(std::nullopt, mav_cmd::kImageStartCapture, kCameraCompid);
        ++images_taken_;
        if (images_->count != 0 && images_taken_ >= images_->count) {
            spdlog::info("camera: interval capture done ({} images)", images_taken_);
            images_.reset();
            return;
        }
    } else {
        log_.warn("interval photo skipped",
                  connected ? "camera: an interval photo skipped: the previous camera call is "
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

void CameraComponent::stop_images() {
    if (images_) {
        spdlog::info("camera: interval capture stopped after {} images", images_taken_);
    }
    images_.reset();
    image_timer_.cancel();
}

}  // namespace gport::mavlink::bridge
