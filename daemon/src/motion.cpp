// Motion: the commands that move the gimbal (a speed braked before it is
// sent, by the one freshness rule), and what ends a motion. The attitude,
// the keepalive's timer, braking a running speed and the failsafe are in
// motion_watch.cpp.
#include "gport/daemon/core/motion.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "gport/daemon/client_log.hpp"

namespace gport::daemon {

namespace gp = gport::protocol;
using Clock = std::chrono::steady_clock;

namespace {

MotionTracker::Options tracker_options(const config::MotionConfig& motion) {
    return {motion.tolerance_deg, motion.timeout, motion.stall};
}

Millis keepalive_period(double rate_hz) {
    return std::chrono::duration_cast<Millis>(std::chrono::duration<double>(1.0 / rate_hz));
}

std::string pid_of(const std::optional<ClientInfo>& client) {
    return client ? std::to_string(client->pid) : std::string("-");
}

std::optional<CommandError> out_of_range_error(const char* name, std::optional<Millis> value,
                                               Millis max) {
    if (!value || (value->count() >= 1 && *value <= max)) {
        return std::nullopt;
    }
    return CommandError{
        ErrorCode::kInvalidParams,
        fmt::format("{} = {} is out of range; allowed 1 to {}", name, value->count(), max.count())};
}

}  // namespace

Motion::Motion(boost::asio::io_context& io, const config::Config& config, GimbalLink& link,
               std::shared_ptr<spdlog::logger> log, const std::optional<AttitudeSample>& latest)
    : durations_(config.keepalive),
      limits_(config.limits),
      failsafe_(config.failsafe),
      stale_after_(config.link.stale_after),
      link_(link),
      log_(std::move(log)),
      latest_(latest),
      keepalive_(keepalive_period(config.keepalive.rate_hz)),
      keepalive_timer_(io),
      tracker_(
          io, tracker_options(config.motion), [this](const MotionEvent& e) { publish(e); },
          latest) {}

void Motion::reload(const config::Config& config) {
    durations_.default_duration = config.keepalive.default_duration;
    durations_.max_duration = config.keepalive.max_duration;
    limits_ = config.limits;
    failsafe_ = config.failsafe;
    tracker_.set_options(tracker_options(config.motion));
}

// ---- speed -------------------------------------------------------------------

Outcome<SpeedRequest> Motion::check_speed(gp::Axes speed, std::optional<Millis> duration,
                                          bool clamp, std::optional<Millis> lease) const {
    const auto max = durations_.max_duration;
    if (auto bad = out_of_range_error("duration_ms", duration, max)) {
        return std::move(*bad);
    }
    if (auto bad = out_of_range_error("lease_ms", lease, max)) {
        return std::move(*bad);
    }
    auto limited = MotionLimits(limits_).speed(speed, clamp);
    if (!limited) {
        return limited.error();
    }
    const auto length = duration.value_or(durations_.default_duration);
    return SpeedRequest{std::move(*limited), length, lease.value_or(length)};
}

// Never towards or past a limit: braked before it is sent. A speed ends an
// angle or centre motion.
Outcome<SpeedStarted> Motion::speed(const ClientInfo& client, SpeedRequest request) {
    auto braked = brake_command(request.speed.axes);
    if (!braked) {
        return braked.error();
    }
    if (!send(gp::Control::speed_of(braked->speed))) {
        return link_.link_down();
    }
    tracker_.end(EndReason::kSuperseded);
    SpeedStarted started;
    if (moves(request.speed.axes) && !moves(braked->speed)) {
        started = stopped_at_limit(client, *braked);
    } else {
        auto begun = keepalive_.start(client, braked->speed, request.duration, request.lease,
                                      braked->braked, Clock::now());
        arm_keepalive();
        started = begun.reply;
        if (begun.event) {
            publish(*begun.event);  // last: the listener may end the motion
        }
    }
    started.speed = braked->speed;
    started.clamped = std::move(request.speed.clamped);
    started.braked = std::move(braked->braked);
    return started;
}

// The one freshness rule (is_fresh), for braking, hold and no_attitude.
Motion::Freshness Motion::freshness(SteadyTime now) const {
    if (!latest_) {
        return {};
    }
    const auto age = std::chrono::duration_cast<Millis>(now - latest_->received);
    return {age, is_fresh(age, stale_after_)};
}

Outcome<Braked> Motion::brake_command(gp::Axes speed) const {
    const auto brake = soft_brake();
    const auto limited = brake.needs_attitude(speed);
    if (limited.empty()) {
        return Braked{speed, {}};
    }
    const auto attitude = freshness(Clock::now());
    if (!attitude.fresh) {
        const auto why = attitude.age
                             ? fmt::format("the latest is {} ms old", attitude.age->count())
                             : std::string("none has arrived yet");
        return CommandError{
            ErrorCode::kLinkDown,
            fmt::format("no fresh attitude from the gimbal ({}; fresh means younger than "
                        "link.stale_ms = {} ms), and braking {} at the soft limits (limits.*) "
                        "needs it; nothing sent",
                        why, stale_after_.count(), fmt::join(limited, ", "))};
    }
    return brake.apply(speed, latest_->attitude.hall, *attitude.age);
}

// Nothing is left to move: the zero speed has gone out; a running motion
// (whoever owns it: this speed would have replaced it) ends at the limit.
SpeedStarted Motion::stopped_at_limit(const ClientInfo& client, const Braked& braked) {
    if (keepalive_.active()) {
        brake_speed(braked);
    } else {
        const ClientLogScope scope(client);
        log_->debug("speed by pid {} braked at the soft limits ({}): nothing moves", client.pid,
                    fmt::join(braked.braked, ", "));
    }
    return SpeedStarted{Millis(0), std::chrono::time_point_cast<WallTime::duration>(
                                       std::chrono::system_clock::now())};
}

// ---- positions -----------------------------------------------------------------

Outcome<Limited> Motion::check_angle(gp::Axes angle, bool clamp) const {
    return MotionLimits(limits_).angle(angle, clamp);
}

Outcome<AngleSent> Motion::angle(const ClientInfo& client, Limited target,
                                 MotionEndCallback on_end) {
    auto sent = position(client, gp::Control::angle_of(target.axes), MotionMode::kAngle,
                         std::move(on_end), target.clamped);
    if (!sent) {
        return sent.error();
    }
    return AngleSent{target.axes, std::move(target.clamped)};
}

// Where the soft limits exclude 0 on an axis, the gimbal's own centre command
// would drive that axis out of range: an angle frame to the clamped centre
// goes instead (for the command, the failsafe and MAVLink's NEUTRAL/RETRACT).
gp::Control Motion::center_control(const Limited& target) {
    return target.clamped.empty() ? gp::Control::center() : gp::Control::angle_of(target.axes);
}

Outcome<AngleSent> Motion::center(const ClientInfo& client, MotionEndCallback on_end) {
    const Limited target = center_target();
    auto sent = position(client, center_control(target), MotionMode::kCenter, std::move(on_end),
                         target.clamped);
    if (!sent) {
        return sent.error();
    }
    return AngleSent{target.axes, target.clamped};
}

Outcome<Done> Motion::lock(const ClientInfo& client) {
    return position(client, gp::Control::lock(), std::nullopt);
}

Outcome<Done> Motion::position(const ClientInfo& client, const gp::Control& control,
                               std::optional<MotionMode> track_as, MotionEndCallback on_end,
                               std::vector<std::string> clamped) {
    if (!send(control)) {
        return link_.link_down();
    }
    end_speed(EndReason::kSuperseded, false);
    if (track_as) {
        tracker_.start(client, *track_as, control.angle, std::move(on_end), std::move(clamped));
        return Done{};
    }
    tracker_.end(EndReason::kSuperseded);
    MotionEvent e;
    e.change = MotionChange::kStarted;
    e.mode = control.mode;
    e.owner = client;
    e.angle = control.angle;
    publish(e);
    return Done{};
}

// ---- endings -------------------------------------------------------------------

// The motion ends whatever happens to the frame; a device that is closed
// owes the zero speed and gets it first when it reopens.
bool Motion::stop() {
    const bool queued = send(gp::Control::stop());
    end(EndReason::kStop, false);
    return queued;
}

void Motion::owner_gone(const ClientInfo& client) {
    const auto running = owner();
    const bool deadman = keepalive_.active() || tracker_.waiting();
    if (running && running->id == client.id && deadman) {
        failsafe(EndReason::kOwnerGone, failsafe_.on_owner_gone, true);
    }
}

void Motion::preempt() {
    end(EndReason::kPreempted, true);
}

void Motion::shutdown() {
    failsafe(EndReason::kShutdown, failsafe_.on_shutdown, true);
}

// The device is closed: nothing can be sent, so neither the zero speed (as
// before) nor "center" (failsafe() says so); a stale attitude is
// kNoAttitude (watch_speed). Never "hold".
void Motion::on_link(LinkState state) {
    if (state == LinkState::kDown) {
        failsafe(EndReason::kLinkDown, failsafe_.on_link_lost, false);
    } else if (state == LinkState::kStale && keepalive_.active()) {
        watch_speed(Clock::now());
    }
}

// At most one of the two runs; the zero speed goes out once, from whichever.
void Motion::end(EndReason reason, bool send_zero) {
    if (tracker_.active()) {
        if (send_zero) {
            send(gp::Control::stop());
        }
        tracker_.end(reason);
        return;
    }
    end_speed(reason, send_zero);
}

// The link queues a stop ahead of everything else, and owes it while the
// device is closed. The motion is gone before anything is told of its end.
void Motion::end_speed(EndReason reason, bool send_zero) {
    auto ended = keepalive_.end(reason);
    if (!ended) {
        return;
    }
    keepalive_timer_.cancel();
    if (send_zero) {
        send(gp::Control::stop());
    }
    publish(*ended);
}

// 0x85 frames are never refused for queue space: a stop goes next, and a
// newer position command replaces a waiting one (write_queue.hpp).
bool Motion::send(const gp::Control& control) {
    const auto kind = control == gp::Control::stop() ? FrameKind::kStop : FrameKind::kMotion;
    return !link_.send(gp::encode(control), kind);
}

// ---- figures and events ----------------------------------------------------------

std::optional<ClientInfo> Motion::owner() const {
    if (auto speed_owner = keepalive_.owner()) {
        return speed_owner;
    }
    return tracker_.owner();
}

std::optional<MotionStatus> Motion::status() const {
    if (auto speed = keepalive_.status(Clock::now())) {
        return speed;
    }
    return tracker_.status();
}

void Motion::publish(const MotionEvent& event) {
    const ClientLogScope scope(event.owner);       // the motion's lines name its owner
    if (event.change == MotionChange::kUpdated) {  // a streaming controller: not news
        const auto& axes = event.mode == MotionMode::kSpeed ? event.speed : event.angle;
        log_->debug("motion updated ({}) by pid {}: {} {} {} {}", to_string(event.mode),
                    pid_of(event.owner), event.mode == MotionMode::kSpeed ? "speed" : "target",
                    axes.roll, axes.pitch, axes.yaw);
    } else if (event.change == MotionChange::kEnded) {
        log_->info("motion ended ({}), owner pid {}{}{}",
                   event.reason ? to_string(*event.reason) : "unknown", pid_of(event.owner),
                   event.detail.empty() ? "" : ": ", event.detail);
    } else {
        log_->info("motion {} ({}) by pid {}", to_string(event.change), to_string(event.mode),
                   pid_of(event.owner));
    }
    if (observer_ != nullptr) {
        observer_->on_motion(event);
    }
}

}  // namespace gport::daemon
