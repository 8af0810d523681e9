#include "gport/daemon/core/keepalive.hpp"

#include <algorithm>

#include "gport/daemon/core/soft_brake.hpp"

namespace gport::daemon {

namespace {

SpeedStarted started_for(Millis duration) {
    const auto wall_end = std::chrono::system_clock::now() + duration;
    return SpeedStarted{duration, std::chrono::time_point_cast<WallTime::duration>(wall_end)};
}

// True when `now` names an axis that `before` does not.
bool adds(const std::vector<std::string>& before, const std::vector<std::string>& now) {
    return merged(before, now).size() > before.size();
}

}  // namespace

Keepalive::Started Keepalive::start(const ClientInfo& owner, protocol::Axes speed, Millis duration,
                                    Millis lease, std::vector<std::string> braked, SteadyTime now) {
    if (motion_ && motion_->owner.id == owner.id) {
        return update(speed, duration, lease, std::move(braked), now);
    }
    const bool replacing = motion_.has_value();
    motion_ = Motion{owner, speed, duration, now, now + duration, now + period_, now + lease, now};
    motion_->braked = std::move(braked);
    return {started_for(duration),
            event(replacing ? MotionChange::kReplaced : MotionChange::kStarted, std::nullopt)};
}

// The same owner's next speed: renews the end (its duration counts from now,
// as for any speed command) and the lease; published later, coalesced, unless
// the last event of the motion is older than kUpdateNoteInterval or the
// update brakes an axis that was not braked before.
Keepalive::Started Keepalive::update(protocol::Axes speed, Millis duration, Millis lease,
                                     std::vector<std::string> braked, SteadyTime now) {
    ++updates_;
    const bool newly_braked = adds(motion_->braked, braked);
    motion_->speed = speed;
    motion_->duration = duration;
    motion_->ends = now + duration;
    motion_->lease_ends = now + lease;
    motion_->next_tick = now + period_;  // the frame just sent counts as a tick
    motion_->braked = std::move(braked);
    const bool note_now = newly_braked || now >= next_note();
    motion_->update_pending = !note_now;
    Started started{started_for(duration), std::nullopt};
    if (note_now) {
        motion_->noted = now;
        started.event = event(MotionChange::kUpdated,
                              newly_braked ? std::optional(EndReason::kLimit) : std::nullopt);
    }
    return started;
}

std::optional<MotionEvent> Keepalive::brake(protocol::Axes speed,
                                            const std::vector<std::string>& braked,
                                            SteadyTime now) {
    if (!motion_) {
        return std::nullopt;
    }
    motion_->braked = merged(motion_->braked, braked);
    motion_->speed = speed;
    if (!moves(speed)) {
        return std::nullopt;
    }
    motion_->next_tick = now + period_;  // the frame sent now counts as a tick
    motion_->update_pending = false;     // this event carries the latest speed
    motion_->noted = now;
    return event(MotionChange::kUpdated, EndReason::kLimit);
}

std::optional<MotionEvent> Keepalive::end(EndReason reason) {
    if (!motion_) {
        return std::nullopt;
    }
    auto ended = event(MotionChange::kEnded, reason);
    motion_.reset();
    return ended;
}

Keepalive::Due Keepalive::due(SteadyTime now) const {
    if (!motion_) {
        return Due::kNothing;
    }
    if (now >= motion_->ends) {
        return Due::kEnd;
    }
    if (now >= motion_->lease_ends) {
        return Due::kLeaseEnd;
    }
    return now >= motion_->next_tick ? Due::kTick : Due::kNothing;
}

std::optional<protocol::Axes> Keepalive::tick(SteadyTime now) {
    if (!motion_ || now < motion_->next_tick) {
        return std::nullopt;
    }
    // Drift-free: from the previous deadline. A loop that stalled for
    // several periods skips the missed ticks instead of bursting them.
    do {
        motion_->next_tick += period_;
    } while (motion_->next_tick <= now);
    return motion_->speed;
}

std::optional<MotionEvent> Keepalive::note(SteadyTime now) {
    if (!motion_ || !motion_->update_pending || now < next_note()) {
        return std::nullopt;
    }
    motion_->update_pending = false;
    motion_->noted = now;
    return event(MotionChange::kUpdated, std::nullopt);
}

SteadyTime Keepalive::wake_at() const {
    auto at = std::min({motion_->next_tick, motion_->ends, motion_->lease_ends});
    if (motion_->update_pending) {
        at = std::min(at, next_note());
    }
    return at;
}

std::optional<ClientInfo> Keepalive::owner() const {
    if (!motion_) {
        return std::nullopt;
    }
    return motion_->owner;
}

std::optional<protocol::Axes> Keepalive::speed() const {
    if (!motion_) {
        return std::nullopt;
    }
    return motion_->speed;
}

// The motion ends at the earlier of its end and its lease's end.
std::optional<MotionStatus> Keepalive::status(SteadyTime now) const {
    if (!motion_) {
        return std::nullopt;
    }
    const auto left =
        std::max(SteadyTime::duration::zero(), std::min(motion_->ends, motion_->lease_ends) - now);
    MotionStatus s{MotionMode::kSpeed, motion_->owner, motion_->speed,
                   std::chrono::duration_cast<Millis>(left)};
    s.elapsed = std::chrono::duration_cast<Millis>(now - motion_->started);
    return s;
}

MotionEvent Keepalive::event(MotionChange change, std::optional<EndReason> reason) const {
    MotionEvent e;
    e.change = change;
    e.mode = MotionMode::kSpeed;
    e.owner = motion_->owner;
    e.speed = motion_->speed;
    e.duration = motion_->duration;
    e.reason = reason;
    if (reason == EndReason::kLimit) {
        e.braked = motion_->braked;
    }
    return e;
}

}  // namespace gport::daemon
