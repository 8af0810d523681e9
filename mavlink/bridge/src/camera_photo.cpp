// The camera component's photos and video: gportd `photo` / `record` with
// the vehicle's position as its `meta`, then the ACK and (photos)
// CAMERA_IMAGE_CAPTURED with the image_index (image_count.hpp), the
// attitude gportd logged for the capture and the vehicle gportd stamped it
// with: its position carried to the instant the frame was on the line and
// the autopilot's UTC then (docs/mavlink.md, "The camera component").
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>

#include "camera_component.hpp"
#include "gport/client/results.hpp"
#include "gport/mavlink/bridge/stream_requests.hpp"
#include "gport/mavlink/enums.hpp"

namespace gport::mavlink::bridge {

namespace {

const char* command_name(std::uint16_t command) {
    return command == mav_cmd::kDoDigicamControl ? "DO_DIGICAM_CONTROL" : "IMAGE_START_CAPTURE";
}

// The photo's params: {"meta": ...} with the position, or {}.
std::string photo_params(const client::CaptureOptions& options) {
    return options.meta.empty() ? std::string("{}") : R"({"meta":)" + options.meta + "}";
}

// The vehicle gportd stamped the capture with, as CAMERA_IMAGE_CAPTURED's
// position (degE7, mm); none when untagged.
std::optional<GlobalPositionInt> stamped_position(const client::CaptureVehicle& v) {
    if (!v.tagged) {
        return std::nullopt;
    }
    GlobalPositionInt p;
    p.lat = static_cast<std::int32_t>(std::lround(v.lat * 1e7));
    p.lon = static_cast<std::int32_t>(std::lround(v.lon * 1e7));
    p.alt = static_cast<std::int32_t>(std::lround(v.alt_msl_m * 1e3));
    p.relative_alt = static_cast<std::int32_t>(std::lround(v.alt_rel_m.value_or(0) * 1e3));
    return p;
}

std::uint64_t utc_now_us() {
    return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::microseconds>(
                                          std::chrono::system_clock::now().time_since_epoch())
                                          .count());
}

}  // namespace

std::optional<GlobalPositionInt> CameraComponent::fresh_position() const {
    if (!position_ || Clock::now() - position_->second >= kPositionMaxAge) {
        return std::nullopt;
    }
    return position_->first;
}

// The vehicle's position as the capture's meta. gportd and gport-mavlink
// ship in one package, so the gportd at the other end knows `meta`.
client::CaptureOptions CameraComponent::capture_options() const {
    client::CaptureOptions options;
    options.meta = position_meta(fresh_position());
    return options;
}

bool CameraComponent::merged_photo(const Requester& from, const CommandLong& command,
                                   std::uint8_t compid) {
    const auto now = Clock::now();
    const PhotoMerge::Sender sender{from.header.sysid, from.header.compid};
    const auto match = photo_merge_.match(sender, host_.vehicle_sysid(), now);
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
        merged_.push_back({from, command.command, compid});
    } else {
        ack(from, command.command, *photo_merge_.result(), compid);
    }
    return true;
}

void CameraComponent::begin_photo(const Requester& from, std::uint16_t command,
                                  std::uint8_t compid) {
    photo_merge_.begun({from.header.sysid, from.header.compid}, Clock::now());
    take_photo(from, command, compid);
}

void CameraComponent::take_photo(const std::optional<Requester>& from, std::uint16_t command,
                                 std::uint8_t compid) {
    call_in_flight_ = true;  // cleared by the call's completion (gportd
                             // completes every pending call, on disconnect too)
    photo_in_flight_ = true;
    // The reply's text, for the capture's stamp beside its report.
    host_.gportd().async_call_json(
        "photo", photo_params(capture_options()),
        [this, from, command, compid](std::optional<client::Error> e, std::string result) {
            client::PhotoReport report;
            client::CaptureStamp stamp;
            if (!e) {
                try {
                    report = client::photo_report_from_json(result);
                    stamp = client::capture_stamp_from_json(result);
                } catch (const client::Error& bad) {
                    log_.warn("gportd photo reply unreadable",
                              "camera: gportd's photo reply is unreadable: " + bad.message());
                }
            }
            photo_done(from, command, compid, e, report, stamp);
        });
}

void CameraComponent::photo_done(const std::optional<Requester>& from, std::uint16_t command,
                                 std::uint8_t compid, const std::optional<client::Error>& error,
                                 const client::PhotoReport& report,
                                 const client::CaptureStamp& stamp) {
    call_in_flight_ = false;
    photo_in_flight_ = false;
    if (from) {
        const std::uint8_t result = error ? mav_result::kDenied : mav_result::kAccepted;
        ack(*from, command, result, compid);
        photo_merge_.done(result);
        for (const auto& merged : merged_) {
            ack(merged.from, merged.command, result, merged.compid);
        }
        merged_.clear();
    }
    // To whoever asked (the requester's origin), else (an interval's
    // photos) to the peer.
    const auto message = make_image_captured(image_captured(error, report, stamp));
    image_history_.add(message);
    send(message, from ? from->origin : Origin{});
}

ImageCapture CameraComponent::image_captured(const std::optional<client::Error>& error,
                                             const client::PhotoReport& report,
                                             const client::CaptureStamp& stamp) {
    const auto& capture = report.capture;
    ImageCapture image;
    image.time_boot_ms = host_.time_boot_ms();
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
    // gportd's stamp when it has the vehicle (one source: the capture);
    // without a vehicle source there, our newest position as before.
    if (stamp.vehicle) {
        image.position = stamped_position(*stamp.vehicle);
        if (stamp.vehicle->utc_us) {
            image.time_utc_us = static_cast<std::uint64_t>(*stamp.vehicle->utc_us);
        }
    } else {
        image.position = fresh_position();
    }
    if (!image.position && !error) {
        warn_no_position(image.image_index);
    }
    // The attitude gportd logged with the capture, else our newest sample.
    image.q = camera_orientation(capture_sample(report.attitude, host_.newest_sample()),
                                 host_.vehicle_yaw_deg(), options_.invert);
    return image;
}

void CameraComponent::warn_no_position(std::int32_t image_index) {
    if (position_warned_) {
        return;
    }
    position_warned_ = true;
    spdlog::warn(no_position_warning(image_index, host_.vehicle_sysid(), kPositionMaxAge,
                                     host_.position_requests()));
}

// record on/off with the position as meta. While gportd's assumed state is
// unknown it refuses `on` without force (-32602), so the request is repeated
// once with force: the MAVLink command says which state the user wants.
void CameraComponent::record(const Requester& from, std::uint16_t command, std::uint8_t compid,
                             bool on, bool force) {
    call_in_flight_ = true;
    host_.gportd().async_record(
        on, force, capture_options(),
        [this, from, command, compid, on, force](std::optional<client::Error> e,
                                                 client::RecordResult) {
            if (e && !force && e->is(client::ErrorCode::kInvalidParams)) {
                spdlog::info("record {}: the recording state is unknown; forcing it",
                             on ? "on" : "off");
                record(from, command, compid, on, true);
                return;
            }
            call_in_flight_ = false;
            if (e) {
                log_.warn("gportd refused record", fmt::format("gportd refused record {}: {}",
                                                               on ? "on" : "off", e->message()));
            } else if (on && !recording_since_) {
                recording_since_ = Clock::now();
            } else if (!on) {
                recording_since_.reset();
            }
            ack(from, command, e ? mav_result::kDenied : mav_result::kAccepted, compid);
            send(capture_status(), from.origin);
        });
}

}  // namespace gport::mavlink::bridge
