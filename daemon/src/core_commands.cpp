// Core's commands: each checks its parameters, then admit() (access and
// control by the Arbiter, then the device), then queues its frame.
#include <fmt/format.h>

#include <boost/asio/post.hpp>

#include "gport/daemon/client_log.hpp"
#include "gport/daemon/core.hpp"
#include "gport/daemon/core/motion_limits.hpp"

namespace gport::daemon {

namespace asio = boost::asio;
namespace gp = gport::protocol;

// ---- checks and the device -----------------------------------------------------

std::optional<CommandError> Core::admit(const ClientInfo& client, Arbiter::Needs needs) const {
    if (auto refused = arbiter_.check(client, needs)) {  // access, then control
        return refused;
    }
    if (!device_ready()) {
        return link_down();
    }
    return std::nullopt;
}

CommandError Core::link_down(std::string_view consequence) const {
    std::string why;
    if (!port_.is_open()) {
        why = "is not open";
    } else if (stopping_) {
        why = "is closing: gportd is shutting down";
    } else {
        why = fmt::format("takes no data ({} frames wait for it)", SerialPort::kMaxQueuedFrames);
    }
    return CommandError{
        ErrorCode::kLinkDown,
        fmt::format("gimbal link down: serial device {} {}{}{}", config_.serial.device, why,
                    consequence.empty() ? "" : "; ", consequence)};
}

bool Core::send(const gp::Frame& frame) {
    return !stopping_ && port_.send(frame);
}

// 0x85 frames are never refused for queue space: a stop goes next, and a
// newer position command replaces a waiting one (write_queue.hpp).
bool Core::send_control(const gp::Control& control) {
    const auto kind = control == gp::Control::stop() ? FrameKind::kStop : FrameKind::kMotion;
    return port_.send(gp::encode(control), kind);
}

// The zero speed goes first (a stop is queued ahead of everything), then the
// position frame behind it, so the gimbal never keeps turning. Hold aims at
// the latest hall (joint) angles, clamped into the soft limits; without a
// sample younger than link.stale_ms it falls back to stop.
void Core::failsafe_end(EndReason reason, config::Failsafe policy, bool send_zero) {
    const auto owner = motion_owner();
    if (!owner) {
        return;
    }
    const ClientLogScope scope(*owner);
    auto action = policy;
    std::string note;
    std::optional<gp::Control> then;
    if (policy == config::Failsafe::kHold) {
        const auto now = std::chrono::steady_clock::now();
        if (!latest_) {
            note = "; no attitude received yet, so stop instead of hold";
        } else if (now - latest_->received > config_.link.stale_after) {
            note = fmt::format(
                "; the latest attitude is {} ms old (stale after {} ms), so stop instead of hold",
                std::chrono::duration_cast<Millis>(now - latest_->received).count(),
                config_.link.stale_after.count());
        } else if (auto limited =
                       MotionLimits(config_.limits).angle(latest_->attitude.hall, true)) {
            then = gp::Control::angle_of(limited->axes);
            note = fmt::format(" at hall roll {:.2f}°, pitch {:.2f}°, yaw {:.2f}°",
                               limited->axes.roll / 100.0, limited->axes.pitch / 100.0,
                               limited->axes.yaw / 100.0);
        }
        if (!then) {
            action = config::Failsafe::kStop;
        }
    } else if (policy == config::Failsafe::kCenter) {
        const Limited centre = MotionLimits(config_.limits).centre();
        then = centre_control(centre);
        if (!centre.clamped.empty()) {
            note = fmt::format(
                " at the centre clamped into the soft limits (roll {:.2f}°, "
                "pitch {:.2f}°, yaw {:.2f}°)",
                centre.axes.roll / 100.0, centre.axes.pitch / 100.0, centre.axes.yaw / 100.0);
        }
    }
    if (then && !port_.is_open()) {
        note += fmt::format("; device closed, so {} ({} not sent)",
                            send_zero ? "only the owed zero speed" : "nothing is sent",
                            config::to_string(action));
        then.reset();
    }
    log_->warn("failsafe {} on {}: motion of owner pid {} ends{}", config::to_string(action),
               to_string(reason), owner->pid, note);
    end_motion(reason, send_zero);  // the motion ends whatever follows
    if (then && !send_control(*then)) {
        log_->warn("failsafe {}: the frame could not be queued", config::to_string(action));
    }
}

std::optional<ClientInfo> Core::motion_owner() const {
    if (auto owner = keepalive_.owner()) {
        return owner;
    }
    return tracker_.owner();
}

// At most one of the two runs; the zero speed goes out once, from whichever.
void Core::end_motion(EndReason reason, bool send_zero) {
    if (tracker_.active()) {
        if (send_zero) {
            send_control(gp::Control::stop());
        }
        tracker_.end(reason);
        return;
    }
    keepalive_.end(reason, send_zero);
}

bool Core::may_command(const ClientInfo& client) const {
    return arbiter_.may_command(client);
}

// ---- commands ----------------------------------------------------------------

Outcome<SpeedStarted> Core::speed(const ClientInfo& client, gp::Axes speed,
                                  std::optional<Millis> duration, bool clamp,
                                  std::optional<Millis> lease) {
    const auto max = config_.keepalive.max_duration;
    if (duration && (duration->count() < 1 || *duration > max)) {
        return CommandError{ErrorCode::kInvalidParams,
                            fmt::format("duration_ms = {} is out of range; allowed 1 to {}",
                                        duration->count(), max.count())};
    }
    if (lease && (lease->count() < 1 || *lease > max)) {
        return CommandError{ErrorCode::kInvalidParams,
                            fmt::format("lease_ms = {} is out of range; allowed 1 to {}",
                                        lease->count(), max.count())};
    }
    auto limited = MotionLimits(config_.limits).speed(speed, clamp);
    if (!limited) {
        return limited.error();
    }
    if (auto refused = admit(client, Arbiter::Needs::kAccessAndControl)) {
        return std::move(*refused);
    }
    auto braked = brake_command(limited->axes);  // never towards or past a limit
    if (!braked) {
        return braked.error();
    }
    if (!send_control(gp::Control::speed_of(braked->speed))) {
        return link_down();
    }
    tracker_.end(EndReason::kSuperseded);  // a speed ends an angle or centre motion
    const auto length = duration.value_or(config_.keepalive.default_duration);
    auto started = moves(limited->axes) && !moves(braked->speed)
                       ? stopped_at_limit(client, *braked)
                       : keepalive_.start(client, braked->speed, length, lease.value_or(length),
                                          braked->braked);
    started.speed = braked->speed;
    started.clamped = std::move(limited->clamped);
    started.braked = std::move(braked->braked);
    return started;
}

// Any client that may command may stop, whoever holds control: stopping is
// always safe. The motion ends whatever happens to the frame; a device that
// is closed owes the zero speed and gets it first when it reopens.
Outcome<Done> Core::stop(const ClientInfo& client) {
    if (auto refused = arbiter_.check(client, Arbiter::Needs::kAccess)) {
        return std::move(*refused);
    }
    const bool queued = send_control(gp::Control::stop());
    end_motion(EndReason::kStop, false);
    if (!queued) {
        return link_down(stopping_ ? ""
                                   : "zero speed will be the first frame sent when it reopens");
    }
    return Done{};
}

Outcome<AngleSent> Core::angle(const ClientInfo& client, gp::Axes angle, bool clamp,
                               MotionEndCallback on_end) {
    auto limited = MotionLimits(config_.limits).angle(angle, clamp);
    if (!limited) {
        return limited.error();
    }
    auto sent = position(client, gp::Control::angle_of(limited->axes), MotionMode::kAngle,
                         std::move(on_end), limited->clamped);
    if (!sent) {
        return sent.error();
    }
    return AngleSent{limited->axes, std::move(limited->clamped)};
}

// Where the soft limits exclude 0 on an axis, the gimbal's own centre command
// would drive that axis out of range: an angle frame to the clamped centre
// goes instead (for the command, the failsafe and MAVLink's NEUTRAL/RETRACT).
gp::Control Core::centre_control(const Limited& centre) const {
    return centre.clamped.empty() ? gp::Control::center() : gp::Control::angle_of(centre.axes);
}

Outcome<AngleSent> Core::center(const ClientInfo& client, MotionEndCallback on_end) {
    const Limited centre = MotionLimits(config_.limits).centre();
    auto sent = position(client, centre_control(centre), MotionMode::kCenter, std::move(on_end),
                         centre.clamped);
    if (!sent) {
        return sent.error();
    }
    return AngleSent{centre.axes, centre.clamped};
}

Outcome<Done> Core::lock(const ClientInfo& client) {
    return position(client, gp::Control::lock(), std::nullopt);
}

// angle and centre become tracked motions (a newer one replaces the running
// one: kReplaced); lock ends any motion (kSuperseded) and is not tracked: it
// has no target.
Outcome<Done> Core::position(const ClientInfo& client, const gp::Control& control,
                             std::optional<MotionMode> track_as, MotionEndCallback on_end,
                             std::vector<std::string> clamped) {
    if (auto refused = admit(client, Arbiter::Needs::kAccessAndControl)) {
        return std::move(*refused);
    }
    if (!send_control(control)) {
        return link_down();
    }
    keepalive_.end(EndReason::kSuperseded, false);
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
    on_motion(e);
    return Done{};
}

Outcome<Done> Core::photo(const ClientInfo& client) {
    return camera(client, gp::CameraAction::kPhoto);
}

Outcome<RecordResult> Core::record(const ClientInfo& client, RecordRequest request) {
    const auto wanted =
        request.on ? std::optional(*request.on ? RecordingState::kOn : RecordingState::kOff)
                   : std::nullopt;
    if (wanted && recording_ == RecordingState::kUnknown && !request.force) {
        return CommandError{
            ErrorCode::kInvalidParams,
            fmt::format("the recording state is unknown (gportd cannot read it from the gimbal, "
                        "and forgets it when the device reopens); send record "
                        "{{\"on\": {}, \"force\": true}} to toggle anyway and take {} as the "
                        "new state",
                        *request.on, *request.on ? "on" : "off")};
    }
    if (wanted && recording_ == *wanted && !request.force) {
        if (auto refused = admit(client, Arbiter::Needs::kAccessAndControl)) {
            return std::move(*refused);
        }
        return RecordResult{false, recording_};
    }
    auto sent = camera(client, gp::CameraAction::kToggleRecording);
    if (!sent) {
        return sent.error();
    }
    if (wanted) {
        recording_ = *wanted;
    } else if (recording_ != RecordingState::kUnknown) {
        recording_ = recording_ == RecordingState::kOn ? RecordingState::kOff : RecordingState::kOn;
    }
    log_->info("recording assumed {}", to_string(recording_));
    return RecordResult{true, recording_};
}

Outcome<Done> Core::camera(const ClientInfo& client, gp::CameraAction action) {
    if (auto refused = admit(client, Arbiter::Needs::kAccessAndControl)) {
        return std::move(*refused);
    }
    if (!send(gp::encode(gp::Camera{action}))) {
        return link_down();
    }
    log_->info("camera {} by pid {}",
               action == gp::CameraAction::kPhoto ? "photo" : "record toggle", client.pid);
    return Done{};
}

// ---- control -------------------------------------------------------------------

Outcome<std::optional<ClientInfo>> Core::acquire(const ClientInfo& client) {
    auto acquired = arbiter_.acquire(client, motion_owner());
    if (!acquired) {
        return acquired.error();
    }
    if (acquired->newly_held) {
        log_->info("control acquired by pid {}", client.pid);
    }
    // The arbiter has recorded the new holder: an observer called from end()
    // sees it.
    if (acquired->preempts) {
        end_motion(EndReason::kPreempted, true);
    }
    return arbiter_.holder();
}

Outcome<std::optional<ClientInfo>> Core::release(const ClientInfo& client) {
    auto released = arbiter_.release(client);
    if (!released) {
        return released.error();
    }
    if (released.value()) {
        log_->info("control released by pid {}", client.pid);
    }
    return arbiter_.holder();
}

// The deadman: a speed motion's owner, or a tracked motion's waiting owner,
// is gone. A tracked motion nobody waits for was a completed command: it
// runs on.
void Core::client_gone(const ClientInfo& client) {
    const auto owner = motion_owner();
    const bool deadman = keepalive_.active() || tracker_.waiting();
    if (owner && owner->id == client.id && deadman) {
        failsafe_end(EndReason::kOwnerGone, config_.failsafe.on_owner_gone, true);
    }
    if (arbiter_.client_gone(client)) {
        log_->info("control released: pid {} disconnected", client.pid);
    }
}

void Core::client_closed(const ClientInfo& client) {
    settings_.forget(client.id);
    arbiter_.forget(client);
}

// ---- settings ------------------------------------------------------------------

void Core::get_settings(const ClientInfo& client, SettingsCallback done) {
    settings(client, std::nullopt, std::move(done));
}

void Core::set_settings(const ClientInfo& client, SettingsChange change, SettingsCallback done) {
    settings(client, change, std::move(done));
}

void Core::settings(const ClientInfo& client, std::optional<SettingsChange> change,
                    SettingsCallback done) {
    auto refused = admit(client, Arbiter::Needs::kAccessAndControl);
    if (!refused) {
        refused = settings_.admit(client.id);
    }
    if (refused) {
        asio::post(io_, [done = std::move(done), e = *refused] { done(e); });
        return;
    }
    auto reply = [done = std::move(done)](Outcome<gp::SettingsBlock> r) {
        if (!r) {
            done(r.error());
            return;
        }
        done(Settings{r->dead_zone, r->follow_speed, r->inverted()});
    };
    if (change) {
        settings_.set(client.id, *change, std::move(reply));
    } else {
        settings_.get(client.id, std::move(reply));
    }
}

}  // namespace gport::daemon
