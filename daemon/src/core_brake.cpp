// Core: braking at the soft limits during speed motions (soft_brake.hpp;
// docs/api.md, "Braking at the soft limits"). A speed command is braked
// before it is sent; the running motion is checked again on every attitude
// sample and every keepalive tick.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "gport/daemon/client_log.hpp"
#include "gport/daemon/core.hpp"

namespace gport::daemon {

namespace gp = gport::protocol;

SoftBrake Core::soft_brake() const {
    return SoftBrake(config_.limits, keepalive_.period());
}

std::optional<Millis> Core::fresh_attitude_age(SteadyTime now) const {
    if (!latest_) {
        return std::nullopt;
    }
    const auto age = std::chrono::duration_cast<Millis>(now - latest_->received);
    if (age >= config_.link.stale_after) {
        return std::nullopt;
    }
    return age;
}

Outcome<Braked> Core::brake_command(gp::Axes speed) const {
    const auto brake = soft_brake();
    const auto limited = brake.needs_attitude(speed);
    if (limited.empty()) {
        return Braked{speed, {}};
    }
    const auto now = std::chrono::steady_clock::now();
    const auto age = fresh_attitude_age(now);
    if (!age) {
        const auto why =
            latest_
                ? fmt::format("the latest is {} ms old",
                              std::chrono::duration_cast<Millis>(now - latest_->received).count())
                : std::string("none has arrived yet");
        return CommandError{
            ErrorCode::kLinkDown,
            fmt::format("no fresh attitude from the gimbal ({}; fresh means younger than "
                        "link.stale_ms = {} ms), and braking {} at the soft limits (limits.*) "
                        "needs it; nothing sent",
                        why, config_.link.stale_after.count(), fmt::join(limited, ", "))};
    }
    return brake.apply(speed, latest_->attitude.hall, *age);
}

// Nothing is left to move: the zero speed has gone out; a running motion
// (whoever owns it: this speed would have replaced it) ends at the limit.
SpeedStarted Core::stopped_at_limit(const ClientInfo& client, const Braked& braked) {
    if (keepalive_.active()) {
        keepalive_.brake(braked.speed, braked.braked);
    } else {
        const ClientLogScope scope(client);
        log_->debug("speed by pid {} braked at the soft limits ({}): nothing moves", client.pid,
                    fmt::join(braked.braked, ", "));
    }
    return SpeedStarted{Millis(0), std::chrono::time_point_cast<WallTime::duration>(
                                       std::chrono::system_clock::now())};
}

void Core::watch_motion() {
    const auto speed = keepalive_.speed();
    if (!speed) {
        return;
    }
    const auto brake = soft_brake();
    if (brake.needs_attitude(*speed).empty()) {
        return;
    }
    const auto age = fresh_attitude_age(std::chrono::steady_clock::now());
    if (!age) {
        // Stale: the same policy as a lost link ("stop" or "center"); the
        // zero speed goes out, the device being open.
        failsafe_end(EndReason::kNoAttitude, config_.failsafe.on_link_lost, true);
        return;
    }
    const auto braked = brake.apply(*speed, latest_->attitude.hall, *age);
    if (braked.braked.empty()) {
        return;
    }
    if (const auto owner = keepalive_.owner()) {
        const ClientLogScope scope(*owner);
        log_->info("braking {} at the soft limits: hall roll {:.2f}°, pitch {:.2f}°, yaw {:.2f}°",
                   fmt::join(braked.braked, ", "), latest_->attitude.hall.roll / 100.0,
                   latest_->attitude.hall.pitch / 100.0, latest_->attitude.hall.yaw / 100.0);
    }
    keepalive_.brake(braked.speed, braked.braked);
}

}  // namespace gport::daemon
