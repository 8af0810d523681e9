#include "bridge.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "gport/mavlink/attitude.hpp"
#include "gport/mavlink/enums.hpp"

namespace gport::mavlink::bridge {

namespace asio = boost::asio;
using namespace std::chrono_literals;

namespace {

constexpr auto kBackoffMax = 5000ms;
constexpr auto kManagerTimeout = 3s;
constexpr std::uint8_t kProvisionalSysid = 1;

}  // namespace

std::uint16_t Bridge::gimbal_flags_default() {
    return gimbal_flags::kRollLock | gimbal_flags::kPitchLock;
}

Bridge::Bridge(asio::io_context& io, Options options)
    : io_(io),
      options_(std::move(options)),
      gportd_(io),
      sysid_(options_.sysid),
      reconnect_timer_(io),
      heartbeat_timer_(io),
      attitude_timer_(io) {}

void Bridge::start() {
    transport_ = open_transport(io_, options_.mavlink);
    transport_->start([this](std::span<const std::uint8_t> bytes) { on_bytes(bytes); });
    gportd_.on_notification([this](const client::Notification& n) { on_notification(n); });
    gportd_.on_disconnect([this](const client::Error& e) { on_disconnected(e.message()); });
    spdlog::info("gport-mavlink: MAVLink on {}, gportd at {}, compid {}, sysid {}",
                 to_string(options_.mavlink), options_.socket, options_.compid,
                 options_.sysid ? std::to_string(*options_.sysid) : "adopted from the autopilot");
    connect();
    heartbeat_tick();
    attitude_tick();
}

// ---- gportd ---------------------------------------------------------------------

void Bridge::connect() {
    gportd_.async_connect(options_.socket, [this](std::optional<client::Error> error) {
        if (!error) {
            on_connected();
            return;
        }
        warn_once(last_connect_error_, "gportd: cannot connect to " + options_.socket + ": " +
                                           error->message() + "; retrying with backoff");
        reconnect_timer_.expires_after(backoff_);
        reconnect_timer_.async_wait([this](boost::system::error_code ec) {
            if (!ec) {
                connect();
            }
        });
        backoff_ = std::min<std::chrono::milliseconds>(backoff_ * 2, kBackoffMax);
    });
}

void Bridge::on_connected() {
    backoff_ = 100ms;
    connected_ = true;
    last_connect_error_.clear();
    filter_.reset();
    spdlog::info("gportd: connected to {}", options_.socket);
    gportd_.async_status([this](std::optional<client::Error> error, client::Status status) {
        if (!error) {
            link_state_ = status.link.state;
        }
    });
    gportd_.async_limits([this](std::optional<client::Error> error, client::Limits limits) {
        if (error) {
            spdlog::warn("gportd: limits unknown ({}); GIMBAL_DEVICE_INFORMATION says NaN",
                         error->message());
            return;
        }
        limits_ = limits;
    });
    gportd_.async_subscribe({"attitude", "link"}, std::max(options_.attitude_rate_hz * 2, 1.0),
                            [](std::optional<client::Error> error, client::Subscription) {
                                if (error) {
                                    spdlog::warn("gportd: subscribe refused: {}", error->message());
                                }
                            });
}

void Bridge::on_disconnected(const std::string& why) {
    if (!connected_) {
        return;
    }
    connected_ = false;
    link_state_.clear();
    sample_.reset();
    spdlog::warn("gportd: connection lost ({}); reconnecting", why);
    backoff_ = 100ms;
    connect();
}

void Bridge::on_notification(const client::Notification& notification) {
    if (const auto* sample = std::get_if<client::AttitudeSample>(&notification)) {
        sample_ = *sample;
    } else if (const auto* link = std::get_if<client::LinkEvent>(&notification)) {
        if (link->state != link_state_) {
            spdlog::info("gportd: link {} ({})", link->state, link->reason);
        }
        link_state_ = link->state;
    }
}

void Bridge::dispatch(Command command) {
    if (const auto* none = std::get_if<NoCommand>(&command)) {
        warn_once(last_mapping_error_, "GIMBAL_DEVICE_SET_ATTITUDE ignored: " + none->reason);
        return;
    }
    last_mapping_error_.clear();
    if (const auto* angle = std::get_if<AngleCommand>(&command)) {
        if (!filter_.pass(angle->target)) {
            return;
        }
    } else {
        filter_.reset();
    }
    if (std::holds_alternative<CenterCommand>(command)) {
        mode_flags_ = gimbal_flags_default() | gimbal_flags::kNeutral;
    } else {
        mode_flags_ = gimbal_flags_default();
    }
    if (!connected_) {
        filter_.reset();
        warn_once(last_motion_error_, "gportd is not connected; the command is dropped");
        return;
    }
    if (motion_in_flight_) {
        motion_pending_ = std::move(command);
        return;
    }
    send_motion(command);
}

void Bridge::send_motion(const Command& command) {
    motion_in_flight_ = true;
    if (const auto* angle = std::get_if<AngleCommand>(&command)) {
        spdlog::debug("angle {:.2f} {:.2f} {:.2f}", angle->target.roll, angle->target.pitch,
                      angle->target.yaw);
        gportd_.async_angle(angle->target, client::AngleOptions{},
                            [this](std::optional<client::Error> e, client::AngleResult) {
                                motion_done(e, "angle");
                            });
    } else if (const auto* speed = std::get_if<SpeedCommand>(&command)) {
        client::SpeedOptions so;
        so.lease = std::chrono::milliseconds(options_.lease_ms);
        gportd_.async_speed(speed->speed, so,
                            [this](std::optional<client::Error> e, client::SpeedResult) {
                                motion_done(e, "speed");
                            });
    } else {
        gportd_.async_center(client::CenterOptions{},
                             [this](std::optional<client::Error> e, client::CenterResult) {
                                 motion_done(e, "center");
                             });
    }
}

void Bridge::motion_done(const std::optional<client::Error>& error, const char* what) {
    motion_in_flight_ = false;
    if (error) {
        filter_.reset();
        warn_once(last_motion_error_,
                  std::string("gportd refused ") + what + ": " + error->message());
    } else {
        last_motion_error_.clear();
    }
    if (motion_pending_ && connected_) {
        auto next = std::move(*motion_pending_);
        motion_pending_.reset();
        send_motion(next);
    } else {
        motion_pending_.reset();
    }
}

// ---- MAVLink --------------------------------------------------------------------

void Bridge::on_bytes(std::span<const std::uint8_t> bytes) {
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
    auto message = decode(frame);
    if (!message) {
        ++ignored_messages_;
        return;
    }
    const Header& from = frame.header;
    if (const auto* hb = std::get_if<Heartbeat>(&*message)) {
        on_heartbeat(from, *hb);
        return;
    }
    if (!sysid_.value()) {
        return;  // not part of a system yet
    }
    const std::uint8_t us = *sysid_.value();
    if (const auto* cmd = std::get_if<CommandLong>(&*message)) {
        if (addressed_to(cmd->target_system, cmd->target_component, us, options_.compid)) {
            on_command(from, *cmd);
        }
    } else if (const auto* set = std::get_if<GimbalDeviceSetAttitude>(&*message)) {
        if (addressed_to(set->target_system, set->target_component, us, options_.compid)) {
            on_set_attitude(*set);
        }
    } else if (const auto* state = std::get_if<AutopilotStateForGimbalDevice>(&*message)) {
        if (addressed_to(state->target_system, state->target_component, us, options_.compid)) {
            on_autopilot_state(*state);
        }
    }
}

void Bridge::on_heartbeat(const Header& header, const Heartbeat& heartbeat) {
    if (sysid_.on_heartbeat(header, heartbeat)) {
        spdlog::info("mavlink: joined system {} (the autopilot's heartbeat)", header.sysid);
    }
    if (sysid_.value() && header.sysid == *sysid_.value() && heartbeat.type != mav_type::kGcs &&
        heartbeat.autopilot != mav_autopilot::kInvalid) {
        manager_seen_ = Clock::now();
    }
}

void Bridge::on_command(const Header& from, const CommandLong& command) {
    switch (command.command) {
        case mav_cmd::kRequestMessage:
            request_message(from, command);
            break;
        case mav_cmd::kImageStartCapture:
        case mav_cmd::kVideoStartCapture:
        case mav_cmd::kVideoStopCapture:
            camera(from, command);
            break;
        default:
            ack(from, command.command, mav_result::kUnsupported);
            break;
    }
}

void Bridge::request_message(const Header& from, const CommandLong& command) {
    const auto id = static_cast<std::uint32_t>(command.param[0]);
    if (id == GimbalDeviceInformation::kId) {
        ack(from, command.command, mav_result::kAccepted);
        send(make_information(time_boot_ms(), limits_, options_.invert));
    } else if (id == Heartbeat::kId) {
        ack(from, command.command, mav_result::kAccepted);
        send_heartbeat();
    } else {
        ack(from, command.command, mav_result::kDenied);
    }
}

void Bridge::camera(const Header& from, const CommandLong& command) {
    if (!connected_) {
        ack(from, command.command, mav_result::kTemporarilyRejected);
        return;
    }
    const std::uint16_t cmd = command.command;
    if (cmd == mav_cmd::kImageStartCapture) {
        gportd_.async_photo([this, from, cmd](std::optional<client::Error> e, client::Done) {
            if (e) {
                spdlog::warn("photo refused: {}", e->message());
            }
            ack(from, cmd, e ? mav_result::kDenied : mav_result::kAccepted);
        });
        return;
    }
    record(from, cmd, cmd == mav_cmd::kVideoStartCapture, false);
}

// record on/off; while gportd's assumed state is unknown it refuses `on`
// without force (-32602), so the request is repeated once with force: the
// MAVLink command says which state the user wants.
void Bridge::record(const Header& from, std::uint16_t cmd, bool on, bool force) {
    gportd_.async_record(
        on, force,
        [this, from, cmd, on, force](std::optional<client::Error> e, client::RecordResult) {
            if (e && !force && e->is(client::ErrorCode::kInvalidParams)) {
                spdlog::info("record {}: the recording state is unknown; forcing it",
                             on ? "on" : "off");
                record(from, cmd, on, true);
                return;
            }
            if (e) {
                spdlog::warn("record {} refused: {}", on ? "on" : "off", e->message());
            }
            ack(from, cmd, e ? mav_result::kDenied : mav_result::kAccepted);
        });
}

void Bridge::on_set_attitude(const GimbalDeviceSetAttitude& message) {
    dispatch(map_set_attitude(message, options_.invert, vehicle_yaw_deg_));
}

void Bridge::on_autopilot_state(const AutopilotStateForGimbalDevice& message) {
    if (auto euler = to_euler(message.q, "q")) {
        vehicle_yaw_deg_ = euler->yaw;
    }
    if (!std::isnan(message.angular_velocity_z)) {
        vehicle_yaw_rate_dps_ = to_degrees(message.angular_velocity_z);
    }
}

void Bridge::ack(const Header& to, std::uint16_t command, std::uint8_t result) {
    CommandAck a;
    a.command = command;
    a.result = result;
    a.target_system = to.sysid;
    a.target_component = to.compid;
    send(a);
}

void Bridge::send(const Message& message) {
    // Before a system id is known only the heartbeat goes out, under the
    // provisional id 1 (the autopilots' default), so that a udpout or serial
    // peer (mavlink-router) learns of us and starts sending.
    const bool heartbeat = std::holds_alternative<Heartbeat>(message);
    if (!transport_ || (!sysid_.value() && !heartbeat)) {
        return;
    }
    const Header header{seq_++, sysid_.value().value_or(kProvisionalSysid), options_.compid};
    const Frame frame = encode(message, header);
    transport_->send(frame.bytes());
}

// ---- timers ----------------------------------------------------------------------

Health Bridge::health() const {
    Health h;
    h.gportd_connected = connected_;
    h.link_state = link_state_;
    h.manager_seen = manager_seen_ && Clock::now() - *manager_seen_ < kManagerTimeout;
    return h;
}

std::uint32_t Bridge::time_boot_ms() const {
    return static_cast<std::uint32_t>(
        std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - started_).count());
}

void Bridge::send_heartbeat() {
    Heartbeat hb;
    hb.type = mav_type::kGimbal;
    hb.autopilot = mav_autopilot::kInvalid;
    hb.system_status = system_status(health());
    send(hb);
}

void Bridge::heartbeat_tick() {
    send_heartbeat();
    heartbeat_timer_.expires_after(1s);
    heartbeat_timer_.async_wait([this](boost::system::error_code ec) {
        if (!ec) {
            heartbeat_tick();
        }
    });
}

void Bridge::attitude_tick() {
    AttitudeInputs in;
    in.sample = sample_;
    in.vehicle_yaw_deg = vehicle_yaw_deg_;
    in.vehicle_yaw_rate_dps = vehicle_yaw_rate_dps_;
    in.mode_flags = mode_flags_;
    in.time_boot_ms = time_boot_ms();
    send(make_attitude_status(in, health(), options_.invert));
    const auto period = std::chrono::duration_cast<Clock::duration>(
        std::chrono::duration<double>(1.0 / options_.attitude_rate_hz));
    // Scheduled from the previous expiry, not from now: the rate does not drift.
    const auto now = Clock::now();
    const auto next = attitude_timer_.expiry() + period;
    attitude_timer_.expires_at(next > now ? next : now + period);
    attitude_timer_.async_wait([this](boost::system::error_code ec) {
        if (!ec) {
            attitude_tick();
        }
    });
}

void Bridge::warn_once(std::string& last, const std::string& text) {
    if (text != last) {
        spdlog::warn("{}", text);
        last = text;
    }
}

}  // namespace gport::mavlink::bridge
