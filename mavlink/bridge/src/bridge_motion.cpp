// The motion path (docs/mavlink.md, "Who moves the gimbal, and the stop"):
// who is obeyed, and how a motion command reaches gportd on a connection
// of its own, so that a stop never waits behind the camera's traffic or a
// flood of targets.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "bridge.hpp"
#include "gport/mavlink/enums.hpp"

namespace gport::mavlink::bridge {

namespace {

bool is_stop(const Command& command) {
    const auto* speed = std::get_if<SpeedCommand>(&command);
    return speed != nullptr && speed->speed.roll == 0 && speed->speed.pitch == 0 &&
           speed->speed.yaw == 0;
}

}  // namespace

// The vehicle's autopilot is the gimbal manager: while it sends
// GIMBAL_DEVICE_SET_ATTITUDE (any, its idle all-NaN stream too), a ground
// station's are not obeyed; they are again kManagerPrecedence after its last.
void Bridge::on_set_attitude(const Header& from, const GimbalDeviceSetAttitude& message) {
    const auto now = Clock::now();
    if (from.sysid == trust_.vehicle()) {
        manager_commands_at_ = now;
    } else if (manager_commands_at_ && now - *manager_commands_at_ < kManagerPrecedence) {
        ++counters_.overruled;
        log_.warn("GIMBAL_DEVICE_SET_ATTITUDE overruled",
                  fmt::format("GIMBAL_DEVICE_SET_ATTITUDE from system {} ignored: the vehicle's "
                              "autopilot (system {}) is the gimbal manager and commands it",
                              from.sysid, trust_.vehicle().value_or(0)));
        return;
    }
    // Every obeyed message times the manager's pace, the rate's lease (rate_lease.hpp).
    rate_lease_.on_message(now);
    dispatch(map_set_attitude(message, options_.invert, vehicle_yaw_deg()));
}

void Bridge::dispatch(Command command) {
    if (std::holds_alternative<IdleCommand>(command)) {
        if (!idle_logged_) {
            spdlog::info(
                "mavlink: the gimbal manager sends no target yet (GIMBAL_DEVICE_SET_ATTITUDE all "
                "NaN, as PX4 does before its first one); holding still");
            idle_logged_ = true;
        }
        return;
    }
    idle_logged_ = false;
    if (const auto* none = std::get_if<NoCommand>(&command)) {
        log_.warn(
            fmt::format("GIMBAL_DEVICE_SET_ATTITUDE ignored: {}", none->kind),
            fmt::format("GIMBAL_DEVICE_SET_ATTITUDE ignored: {}: {}", none->kind, none->reason));
        return;
    }
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
        log_.warn("gportd not connected: command dropped",
                  "gportd is not connected; the command is dropped");
        return;
    }
    // The newest command replaces the one waiting; a stop goes at once.
    motion_pending_ = std::move(command);
    send_pending();
}

// One motion at gportd at a time, but a stop, which goes even beside one
// in flight; within kMotionPerSecond, of which kStopReserve only a stop
// may spend: gportd (200 requests/s by default) never pauses the motion
// connection, so the next stop is read at once.
void Bridge::send_pending() {
    if (!motion_pending_ || !connected_) {
        return;
    }
    const bool stop = is_stop(*motion_pending_);
    if (motion_in_flight_ > 0 && !stop) {
        return;  // motion_done sends it
    }
    const double keep = stop ? 0 : kStopReserve;
    const auto now = Clock::now();
    if (motion_budget_.level(now) < keep + 1 || !motion_budget_.take(now)) {
        const auto at = now + motion_budget_.wait_for(now, keep + 1);
        if (!motion_timer_armed_ || motion_timer_.expiry() > at) {
            motion_timer_armed_ = true;
            motion_timer_.expires_at(at);
            motion_timer_.async_wait(
                [this, generation = ++motion_timer_generation_](boost::system::error_code ec) {
                    if (!ec && generation == motion_timer_generation_) {
                        motion_timer_armed_ = false;
                        send_pending();
                    }
                });
        }
        return;
    }
    auto command = std::move(*motion_pending_);
    motion_pending_.reset();
    send_motion(command);
}

void Bridge::send_motion(const Command& command) {
    ++motion_in_flight_;
    const auto sent = ++motion_sent_;
    if (const auto* angle = std::get_if<AngleCommand>(&command)) {
        spdlog::debug("angle {:.2f} {:.2f} {:.2f}", angle->target.roll, angle->target.pitch,
                      angle->target.yaw);
        motion_.async_angle(angle->target, client::AngleOptions{},
                            [this](std::optional<client::Error> e, client::AngleResult) {
                                motion_done(e, "angle");
                            });
    } else if (const auto* speed = std::get_if<SpeedCommand>(&command)) {
        motion_.async_speed(
            speed->speed, speed_options(rate_lease_.current()),
            [this, command, sent](std::optional<client::Error> e, client::SpeedResult) {
                // Sent again with the shorter lease, unless a newer command went.
                if (e && lease_refused(*e) && sent == motion_sent_) {
                    motion_pending_ = motion_pending_.value_or(command);
                    e.reset();
                }
                motion_done(e, "speed");
            });
    } else {
        motion_.async_center(client::CenterOptions{},
                             [this](std::optional<client::Error> e, client::CenterResult) {
                                 motion_done(e, "center");
                             });
    }
}

// gportd refused the lease (or the duration, the same value) as longer
// than its keepalive.max_duration_ms (the message names it): the ceiling
// becomes that, and the speed is sent again.
bool Bridge::lease_refused(const client::Error& error) {
    const auto max = max_lease_in(error.message());
    if (!error.is(client::ErrorCode::kInvalidParams) || !max || *max >= rate_lease_.ceiling()) {
        return false;
    }
    spdlog::info(
        "gportd allows leases up to {} ms (keepalive.max_duration_ms); rate leases are "
        "capped there",
        max->count());
    rate_lease_.set_ceiling(*max);
    return true;
}

void Bridge::motion_done(const std::optional<client::Error>& error, const char* what) {
    --motion_in_flight_;
    if (error) {
        filter_.reset();
        log_.warn(std::string("gportd refused ") + what,
                  std::string("gportd refused ") + what + ": " + error->message());
    }
    if (connected_) {
        send_pending();
    } else {
        motion_pending_.reset();
    }
}

}  // namespace gport::mavlink::bridge
