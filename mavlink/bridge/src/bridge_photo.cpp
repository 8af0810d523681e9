// The camera component's photos: gportd `photo` with the vehicle's
// position as its `meta`, then the ACK and CAMERA_IMAGE_CAPTURED with the
// image_index (image_count.hpp) and the attitude gportd logged for the
// capture (docs/mavlink.md, "The camera component").
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>

#include "bridge.hpp"
#include "gport/mavlink/enums.hpp"

namespace gport::mavlink::bridge {

namespace {

const char* command_name(std::uint16_t command) {
    return command == mav_cmd::kDoDigicamControl ? "DO_DIGICAM_CONTROL" : "IMAGE_START_CAPTURE";
}

std::uint64_t utc_now_us() {
    return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::microseconds>(
                                          std::chrono::system_clock::now().time_since_epoch())
                                          .count());
}

}  // namespace

std::optional<GlobalPositionInt> Bridge::fresh_position() const {
    if (!position_ || Clock::now() - position_->second >= kPositionMaxAge) {
        return std::nullopt;
    }
    return position_->first;
}

// The vehicle's position as the capture's meta. gportd and gport-mavlink
// ship in one package, so the gportd at the other end knows `meta`.
client::CaptureOptions Bridge::capture_options() const {
    client::CaptureOptions options;
    options.meta = position_meta(fresh_position());
    return options;
}

bool Bridge::merged_photo(const Requester& from, const CommandLong& command) {
    const auto now = Clock::now();
    const PhotoMerge::Sender sender{from.header.sysid, from.header.compid};
    const auto match = photo_merge_.match(sender, *trust_.vehicle(), now);
    if (match == PhotoMerge::Match::kNew) {
        return false;
    }
    spdlog::info(
        "camera: {} from system {} component {} came {:.1f} ms after the command of the photo "
        "{}: the same photo (one command, one photo), answered with its result",
        command_name(command.command), sender.sysid, sender.compid,
        std::chrono::duration<double, std::milli>(photo_merge_.since_begun(now)).count(),
        match == PhotoMerge::Match::kDone ? "just taken" : "in flight");
    if (match == PhotoMerge::Match::kInFlight) {
        merged_.emplace_back(from, command.command);
    } else {
        ack(from, command.command, *photo_merge_.result(), kCameraCompid);
    }
    return true;
}

void Bridge::begin_photo(const Requester& from, std::uint16_t command) {
    photo_merge_.begun({from.header.sysid, from.header.compid}, Clock::now());
    take_photo(from, command);
}

void Bridge::take_photo(const std::optional<Requester>& from, std::uint16_t command) {
    camera_in_flight_ = true;  // cleared by the call's completion
    photo_in_flight_ = true;
    gportd_.async_photo_report(
        capture_options(),
        [this, from, command](std::optional<client::Error> e, client::PhotoReport report) {
            photo_done(from, command, e, report);
        });
}

void Bridge::photo_done(const std::optional<Requester>& from, std::uint16_t command,
                        const std::optional<client::Error>& error,
                        const client::PhotoReport& report) {
    const auto& capture = report.capture;
    camera_in_flight_ = false;
    photo_in_flight_ = false;
    if (from) {
        const std::uint8_t result = error ? mav_result::kDenied : mav_result::kAccepted;
        ack(*from, command, result, kCameraCompid);
        photo_merge_.done(result);
        for (const auto& [requester, merged] : merged_) {
            ack(requester, merged, result, kCameraCompid);
        }
        merged_.clear();
    }
    ImageCapture image;
    image.time_boot_ms = time_boot_ms();
    image.time_utc_us = capture && capture->utc_us ? *capture->utc_us : utc_now_us();
    image.success = !error;
    if (error) {
        log_.warn("gportd refused photo", "gportd refused photo: " + error->message());
    } else {
        std::optional<Error> unsaved;
        image.image_index = image_count_.add(unsaved);
        spdlog::info("camera: image_index {} is gportd's capture {}", image.image_index,
                     capture ? std::to_string(capture->index) : std::string("(not reported)"));
        if (unsaved) {
            log_.warn("camera: image count not stored",
                      "camera: the image count could not be stored (" + unsaved->message +
                          "); after a restart image_index may repeat");
        }
    }
    image.position = fresh_position();
    if (!image.position && !error) {
        warn_no_position(image.image_index);
    }
    // The attitude gportd logged with the capture, else our newest sample.
    image.q = camera_orientation(capture_sample(report.attitude, sample_), vehicle_yaw_deg(),
                                 options_.invert);
    // To whoever asked (the requester's origin), else (an interval's
    // photos) to the peer.
    send(make_image_captured(image), from ? from->origin : Origin{}, kCameraCompid);
}

}  // namespace gport::mavlink::bridge
