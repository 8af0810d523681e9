// The MAVLink side of the Bridge: frames in (gated: signature, trust,
// addressing), the messages they carry, and frames out (signed with a key).
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>

#include "bridge.hpp"
#include "gport/mavlink/attitude.hpp"
#include "gport/mavlink/bridge/camera.hpp"
#include "gport/mavlink/bridge/position.hpp"
#include "gport/mavlink/enums.hpp"

namespace gport::mavlink::bridge {

namespace {

constexpr std::uint8_t kProvisionalSysid = 1;

}  // namespace

void Bridge::on_bytes(std::span<const std::uint8_t> bytes, bool fresh_source) {
    if (fresh_source) {
        decoder_.reset();  // no frame of two senders' bytes
    }
    const auto before = decoder_.stats();
    decoder_.feed(bytes, [this](const FrameView& frame) { on_frame(frame); });
    const auto& after = decoder_.stats();
    const auto bad = (after.crc_errors - before.crc_errors) +
                     (after.length_errors - before.length_errors) +
                     (after.header_errors - before.header_errors);
    if (bad > 0) {
        spdlog::debug("mavlink: {} malformed frame(s) skipped ({} CRC errors so far)", bad,
                      after.crc_errors);
    }
}

void Bridge::on_frame(const FrameView& frame) {
    // 1. The signature, before anything reads the frame's content.
    if (signing_ && !signing_->admit(frame)) {
        return;
    }
    if (!signing_ && frame.is_signed) {
        ++counters_.signed_no_key;
        log_.warn("signed frames dropped: no key",
                  fmt::format("mavlink: dropped a signed frame from system {} component {}: "
                              "gport-mavlink has no signing key to check it with "
                              "(--signing-key; the vehicle signs its link)",
                              frame.header.sysid, frame.header.compid));
        return;
    }
    auto message = decode(frame);
    if (!message) {
        ++counters_.undecodable;
        return;
    }
    // 2. The trust rules; 3. the addressing, in handle().
    if (!admitted(frame, *message)) {
        return;
    }
    ++counters_.accepted;
    if (auto peer = transport_->accept_sender()) {
        log_peer(frame, *peer);
    }
    handle(frame.header, *message);
}

// Every change of the reply peer is an event worth auditing (a local
// spoofer taking it over, without a key): the first ones of each minute are
// named, the rest counted, with no lifetime cap.
void Bridge::log_peer(const FrameView& frame, const std::string& peer) {
    log_.note(
        spdlog::level::info, "mavlink: reply peer changed",
        [&] {
            return fmt::format(
                "mavlink: replying to {} (it sent an accepted frame, from system {} component "
                "{})",
                peer, frame.header.sysid, frame.header.compid);
        },
        kPeerLinesPerMinute);
}

bool Bridge::admitted(const FrameView& frame, const Message& message) {
    if (const auto* hb = std::get_if<Heartbeat>(&message);
        hb != nullptr && trust_.on_heartbeat(frame.header, *hb)) {
        spdlog::warn(
            "mavlink: adopted system {} as the vehicle (--sysid auto: the first autopilot "
            "heartbeat; anyone on the link can claim it)",
            frame.header.sysid);
    }
    const TrustVerdict verdict = trust_.judge(frame.header, frame.msgid);
    // Only an allowed system's frame moves our signing clock (issue 30): a
    // key holder we ignore must not push it ahead.
    if (signing_ && (verdict == TrustVerdict::kTrusted || verdict == TrustVerdict::kNotVehicle)) {
        signing_->follow(frame);
    }
    if (verdict == TrustVerdict::kTrusted) {
        return true;
    }
    refuse(frame, verdict);
    return false;
}

void Bridge::refuse(const FrameView& frame, TrustVerdict verdict) {
    if (verdict == TrustVerdict::kNotVehicle) {
        ++counters_.gcs_heartbeats;  // normal: it just is no vehicle state
        return;
    }
    ++counters_.untrusted;
    if (verdict == TrustVerdict::kNoVehicle) {
        log_.warn("frames ignored: no vehicle yet",
                  "mavlink: ignoring frames until the vehicle's autopilot heartbeat adopts a "
                  "system id (--sysid auto)");
        return;
    }
    if (verdict == TrustVerdict::kOwnEcho) {
        log_.warn("mavlink: own frames sent back", [&] {
            return fmt::format(
                "mavlink: ignoring a frame from system {} component {} ({}): that is us, so it "
                "is our own frame sent back (a routing loop, or a replay); further ones are "
                "counted, one line a minute",
                frame.header.sysid, frame.header.compid, message_name(frame.msgid));
        });
        return;
    }
    log_.warn("mavlink: untrusted frames ignored", [&] {
        return fmt::format(
            "mavlink: ignoring system {} component {} ({}): it is neither the vehicle "
            "(system {}) nor a ground station (--gcs-sysid {}); further untrusted frames "
            "are counted, one line a minute",
            frame.header.sysid, frame.header.compid, message_name(frame.msgid),
            trust_.vehicle().value_or(0), to_string(options_.gcs_sysids));
    });
}

void Bridge::handle(const Header& from, const Message& message) {
    const std::uint8_t us = *trust_.vehicle();
    if (const auto* hb = std::get_if<Heartbeat>(&message)) {
        on_heartbeat(from, *hb);
    } else if (const auto* cmd = std::get_if<CommandLong>(&message)) {
        if (camera_.addressed(*cmd)) {
            camera_.on_command({from, transport_->origin()}, *cmd);
        } else if (addressed_to(cmd->target_system, cmd->target_component, us, options_.compid)) {
            on_command({from, transport_->origin()}, *cmd);
        }
    } else if (const auto* set = std::get_if<GimbalDeviceSetAttitude>(&message)) {
        if (addressed_to(set->target_system, set->target_component, us, options_.compid)) {
            on_set_attitude(from, *set);
        }
    } else if (const auto* state = std::get_if<AutopilotStateForGimbalDevice>(&message)) {
        if (addressed_to(state->target_system, state->target_component, us, options_.compid)) {
            on_autopilot_state(*state);
        }
    } else if (const auto* attitude = std::get_if<Attitude>(&message)) {
        on_attitude(from, *attitude);
    } else if (const auto* position = std::get_if<GlobalPositionInt>(&message)) {
        on_position(from, *position);
    } else if (const auto* gps = std::get_if<GpsRawInt>(&message)) {
        on_gps(from, *gps);
    } else if (const auto* time = std::get_if<SystemTime>(&message)) {
        on_system_time(from, *time);
    } else if (const auto* answer = std::get_if<CommandAck>(&message)) {
        if (addressed_to(answer->target_system, answer->target_component, us, options_.compid)) {
            on_ack(from, *answer);
        }
    }
}

void Bridge::on_heartbeat(const Header& header, const Heartbeat& heartbeat) {
    // Trusted heartbeats come from the vehicle's system only (trust.hpp);
    // of those, an autopilot's says that a gimbal manager is present.
    if (header.sysid == trust_.vehicle() && is_autopilot(heartbeat)) {
        manager_seen_ = Clock::now();
        if (header.compid == mav_comp_id::kAutopilot1) {
            streams_.on_heartbeat(*manager_seen_);
        }
    }
}

void Bridge::on_command(const Requester& from, const CommandLong& command) {
    switch (command.command) {
        case mav_cmd::kRequestMessage:
            request_message(from, command);
            break;
        case mav_cmd::kImageStartCapture:
        case mav_cmd::kImageStopCapture:
        case mav_cmd::kVideoStartCapture:
        case mav_cmd::kVideoStopCapture:
            camera_.on_gimbal_command(from, command, 0);  // one photo and record path
            break;
        default:
            ack(from, command.command, mav_result::kUnsupported);
            break;
    }
}

void Bridge::request_message(const Requester& from, const CommandLong& command) {
    // A whole number from 0 to 2^24-1; anything else (NaN, -1, 5e9, 283.7)
    // is no message id: DENIED.
    const auto id = requested_message(command).value_or(0xFFFFFFFF);
    spdlog::debug("mavlink: REQUEST_MESSAGE({}) from system {} component {} to {}/{}", id,
                  from.header.sysid, from.header.compid, command.target_system,
                  command.target_component);
    if (id == GimbalDeviceInformation::kId) {
        ack(from, command.command, mav_result::kAccepted);
        send(make_information(time_boot_ms(), limits_, options_.invert), from.origin);
    } else if (id == Heartbeat::kId) {
        ack(from, command.command, mav_result::kAccepted);
        send_heartbeat(from.origin);
    } else {
        ack(from, command.command, mav_result::kDenied);
    }
}

void Bridge::on_autopilot_state(const AutopilotStateForGimbalDevice& message) {
    if (auto euler = to_euler(message.q, "q")) {
        const float rate = message.angular_velocity_z;
        vehicle_yaw_.from_autopilot_state(
            euler->yaw, std::isfinite(rate) ? std::optional(to_degrees(rate)) : std::nullopt,
            Clock::now());
    }
}

// ATTITUDE from the vehicle's autopilot only (as positions: position.hpp).
void Bridge::on_attitude(const Header& from, const Attitude& message) {
    if (from.sysid != trust_.vehicle() || from.compid != mav_comp_id::kAutopilot1 ||
        !std::isfinite(message.yaw)) {
        return;
    }
    streams_.on_message(Attitude::kId, Clock::now());
    const float rate = message.yawspeed;
    vehicle_yaw_.from_attitude(to_degrees(message.yaw),
                               std::isfinite(rate) ? std::optional(to_degrees(rate)) : std::nullopt,
                               Clock::now());
}

std::optional<double> Bridge::vehicle_yaw_deg() {
    const auto now = Clock::now();
    const YawSource source = vehicle_yaw_.source(now);
    if (source != yaw_source_) {
        spdlog::info(
            "mavlink: the vehicle's yaw (earth-frame targets, the camera's heading) now "
            "from {}{}",
            to_string(source),
            source == YawSource::kAttitude ? " (no fresh AUTOPILOT_STATE_FOR_GIMBAL_DEVICE)"
            : source == YawSource::kNone
                ? ": none fresh from the vehicle's autopilot; earth-frame targets are "
                  "refused until one comes"
                : "");
        yaw_source_ = source;
    }
    const auto reading = vehicle_yaw_.at(now);
    return reading ? std::optional(reading->yaw_deg) : std::nullopt;
}

void Bridge::on_position(const Header& from, const GlobalPositionInt& message) {
    if (auto problem = position_problem(from, message)) {
        ++counters_.bad_positions;
        log_.warn("mavlink: positions dropped", [&] {
            return fmt::format(
                "mavlink: dropped GLOBAL_POSITION_INT from system {} component {}: {}; photos "
                "keep the last valid position while it is under 1 s old (further ones are "
                "counted, one line a minute)",
                from.sysid, from.compid, *problem);
        });
        return;
    }
    const auto now = Clock::now();
    camera_.on_position(message, now);
    const auto yaw = vehicle_yaw_.at(now);
    vehicle_.on_position(message, yaw ? yaw->rate_dps : std::nullopt, now);
    streams_.on_message(GlobalPositionInt::kId, now);
}

// GPS_RAW_INT and SYSTEM_TIME from the vehicle's autopilot only, as positions.
void Bridge::on_gps(const Header& from, const GpsRawInt& message) {
    if (from.sysid != trust_.vehicle() || from.compid != mav_comp_id::kAutopilot1) {
        return;
    }
    const auto now = Clock::now();
    vehicle_.on_gps(message, now);
    streams_.on_message(GpsRawInt::kId, now);
}

void Bridge::on_system_time(const Header& from, const SystemTime& message) {
    if (from.sysid != trust_.vehicle() || from.compid != mav_comp_id::kAutopilot1) {
        return;
    }
    vehicle_.on_system_time(message);
    streams_.on_message(SystemTime::kId, Clock::now());
}

void Bridge::ack(const Requester& to, std::uint16_t command, std::uint8_t result,
                 std::uint8_t compid) {
    CommandAck a;
    a.command = command;
    a.result = result;
    a.target_system = to.header.sysid;
    a.target_component = to.header.compid;
    send(a, to.origin, compid);
}

void Bridge::send(const Message& message, const Origin& to, std::uint8_t compid) {
    // With --sysid auto, before the vehicle is adopted only the heartbeat
    // goes out, under the provisional id 1 (the autopilots' default), so that
    // a udpout or serial peer (mavlink-router) learns of us and starts
    // sending. udpin sends nothing before a frame was accepted (no peer).
    const bool heartbeat = std::holds_alternative<Heartbeat>(message);
    if (!transport_ || (!trust_.vehicle() && !heartbeat)) {
        return;
    }
    if (!transport_->can_send(to)) {
        transport_->count_unsent();  // before signing: no timestamp spent on it
        return;
    }
    const std::uint8_t from = compid != 0 ? compid : options_.compid;
    std::uint8_t& seq = from == options_.compid ? seq_ : camera_seq_;
    const Header header{seq++, trust_.vehicle().value_or(kProvisionalSysid), from};
    Frame frame = encode(message, header, signing_ != nullptr);
    if (signing_) {
        signing_->sign(frame);
    }
    transport_->send_to(frame.bytes(), to);
}

}  // namespace gport::mavlink::bridge
