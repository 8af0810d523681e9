// Motion: watching a running motion. The attitude, the keepalive's timer (a
// tick re-sends the speed after braking it), braking the running speed at
// the soft limits (soft_brake.hpp; docs/api.md, "Braking at the soft
// limits"), and the failsafe policies (docs/api.md, "Failsafe").
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <string>

#include "gport/daemon/client_log.hpp"
#include "gport/daemon/core/motion.hpp"

namespace gport::daemon {

namespace gp = gport::protocol;
using Clock = std::chrono::steady_clock;

namespace {

// "roll 1.00°, pitch -2.50°, yaw 0.00°", for the journal.
std::string axes_text(const gp::Axes& axes) {
    const auto [roll, pitch, yaw] = gp::degrees_of(axes);
    return fmt::format("roll {:.2f}°, pitch {:.2f}°, yaw {:.2f}°", roll, pitch, yaw);
}

}  // namespace

// ---- the attitude ------------------------------------------------------------

void Motion::on_attitude() {
    if (keepalive_.active()) {
        watch_speed(Clock::now());  // braking reacts to every sample, not only to ticks
    }
}

void Motion::on_attitude_published(const AttitudeSample& sample) {
    tracker_.on_attitude(sample);
}

// ---- braking -----------------------------------------------------------------

void Motion::watch_speed(SteadyTime now) {
    const auto speed = keepalive_.speed();
    if (!speed) {
        return;
    }
    const auto brake = soft_brake();
    if (brake.needs_attitude(*speed).empty()) {
        return;
    }
    const auto attitude = freshness(now);
    if (!attitude.fresh) {
        // Stale: the same policy as a lost link ("stop" or "center"); the
        // zero speed goes out, the device being open.
        failsafe(EndReason::kNoAttitude, failsafe_.on_link_lost, true);
        return;
    }
    const auto braked = brake.apply(*speed, latest_->attitude.hall, *attitude.age);
    if (braked.braked.empty()) {
        return;
    }
    if (const auto owner = keepalive_.owner()) {
        const ClientLogScope scope(*owner);
        const auto& hall = latest_->attitude.hall;
        log_->info("braking {} at the soft limits: hall {}", fmt::join(braked.braked, ", "),
                   axes_text(hall));
    }
    brake_speed(braked);
}

// Sends the braked speed at once and publishes kUpdated (reason kLimit), or
// ends the motion (kLimit, zero speed) when no axis is left moving.
void Motion::brake_speed(const Braked& braked) {
    auto updated = keepalive_.brake(braked.speed, braked.braked, Clock::now());
    if (!updated) {
        end_speed(EndReason::kLimit, true);
        return;
    }
    send_keepalive(braked.speed);
    arm_keepalive();
    publish(*updated);  // last: the listener may end the motion
}

// ---- the keepalive -----------------------------------------------------------

void Motion::arm_keepalive() {
    keepalive_timer_.expires_at(keepalive_.wake_at());
    keepalive_timer_.async_wait([this](boost::system::error_code ec) {
        if (!ec && keepalive_.active()) {
            on_keepalive_timer();
        }
    });
}

// A tick: the motion's end or its lease's end, else braking by the latest
// attitude (which may send at once, or end the motion), the speed re-sent,
// and a coalesced update published.
void Motion::on_keepalive_timer() {
    const auto now = Clock::now();
    switch (keepalive_.due(now)) {
        case Keepalive::Due::kEnd:
            end_speed(EndReason::kDuration, true);
            return;
        case Keepalive::Due::kLeaseEnd:
            // A hung controller is an owner gone as far as the gimbal cares.
            failsafe(EndReason::kLeaseExpired, failsafe_.on_owner_gone, true);
            return;
        case Keepalive::Due::kTick:
            watch_speed(now);
            if (!keepalive_.active()) {
                return;
            }
            if (auto speed = keepalive_.tick(now)) {  // none when a brake just sent it
                send_keepalive(*speed);
            }
            break;
        case Keepalive::Due::kNothing:
            break;
    }
    auto note = keepalive_.note(now);
    arm_keepalive();
    if (note) {
        publish(*note);  // last: the listener may end the motion
    }
}

void Motion::send_keepalive(gp::Axes speed) {
    if (send(gp::Control::speed_of(speed))) {
        ++keepalive_frames_;
    }
}

// ---- the failsafe ------------------------------------------------------------

// The zero speed goes first (a stop is queued ahead of everything), then the
// position frame behind it, so the gimbal never keeps turning.
void Motion::failsafe(EndReason reason, config::Failsafe policy, bool send_zero) {
    const auto running = owner();
    if (!running) {
        return;
    }
    const ClientLogScope scope(*running);
    auto action = policy;
    std::string note;
    auto then = failsafe_frame(action, note);
    if (then && !link_.open()) {
        note += fmt::format("; device closed, so {} ({} not sent)",
                            send_zero ? "only the owed zero speed" : "nothing is sent",
                            config::to_string(action));
        then.reset();
    }
    log_->warn("failsafe {} on {}: motion of owner pid {} ends{}", config::to_string(action),
               to_string(reason), running->pid, note);
    end(reason, send_zero);  // the motion ends whatever follows
    if (then && !send(*then)) {
        log_->warn("failsafe {}: the frame could not be queued", config::to_string(action));
    }
}

// Hold aims at the latest hall (joint) angles, clamped into the soft limits;
// without a fresh sample it falls back to stop. Center aims at the centre
// clamped into the soft limits.
std::optional<gp::Control> Motion::failsafe_frame(config::Failsafe& action,
                                                  std::string& note) const {
    if (action == config::Failsafe::kHold) {
        const auto attitude = freshness(Clock::now());
        std::optional<Limited> hold;
        if (!attitude.age) {
            note = "; no attitude received yet, so stop instead of hold";
        } else if (!attitude.fresh) {
            note = fmt::format(
                "; the latest attitude is {} ms old (stale after {} ms), so stop instead of hold",
                attitude.age->count(), stale_after_.count());
        } else if (auto limited = MotionLimits(limits_).angle(latest_->attitude.hall, true)) {
            hold = std::move(*limited);
        }
        if (!hold) {
            action = config::Failsafe::kStop;
            return std::nullopt;
        }
        note = " at hall " + axes_text(hold->axes);
        return gp::Control::angle_of(hold->axes);
    }
    if (action == config::Failsafe::kCenter) {
        const Limited target = center_target();
        if (!target.clamped.empty()) {
            note = " at the centre clamped into the soft limits (" + axes_text(target.axes) + ")";
        }
        return center_control(target);
    }
    return std::nullopt;
}

}  // namespace gport::daemon
