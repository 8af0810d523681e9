#include "gport/daemon/core/keepalive.hpp"

#include <algorithm>

#include "gport/daemon/core/soft_brake.hpp"

namespace gport::daemon {

using Clock = std::chrono::steady_clock;

Keepalive::Keepalive(boost::asio::io_context& io, Millis period, Send send, Emit emit, Check check,
                     Expire expire)
    : timer_(io),
      period_(period),
      send_(std::move(send)),
      emit_(std::move(emit)),
      check_(std::move(check)),
      expire_(std::move(expire)) {}

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

SpeedStarted Keepalive::start(const ClientInfo& owner, protocol::Axes speed, Millis duration,
                              Millis lease, std::vector<std::string> braked) {
    if (motion_ && motion_->owner.id == owner.id) {
        return update(speed, duration, lease, std::move(braked));
    }
    const bool replacing = motion_.has_value();
    const auto now = Clock::now();
    motion_ = Motion{owner, speed, duration, now, now + duration, now + period_, now + lease, now};
    motion_->braked = std::move(braked);
    arm();
    const auto started = started_for(duration);
    // Last, and nothing of motion_ afterwards: the listener may end it
    // (its owner dropped for a full outbox) before emit_ returns.
    emit_(event(replacing ? MotionChange::kReplaced : MotionChange::kStarted, std::nullopt));
    return started;
}

// The same owner's next speed: renews the end (its duration counts from now,
// as for any speed command) and the lease; published later, coalesced, unless
// the last event of the motion is older than kUpdateNoteInterval or the
// update brakes an axis that was not braked before.
SpeedStarted Keepalive::update(protocol::Axes speed, Millis duration, Millis lease,
                               std::vector<std::string> braked) {
    ++updates_;
    const auto now = Clock::now();
    const bool newly_braked = adds(motion_->braked, braked);
    motion_->speed = speed;
    motion_->duration = duration;
    motion_->ends = now + duration;
    motion_->lease_ends = now + lease;
    motion_->next_tick = now + period_;  // the frame just sent counts as a tick
    motion_->braked = std::move(braked);
    const bool note_now = newly_braked || now >= next_note();
    motion_->update_pending = !note_now;
    if (note_now) {
        motion_->noted = now;
    }
    arm();
    const auto started = started_for(duration);
    if (note_now) {  // last, as in start()
        emit_(event(MotionChange::kUpdated,
                    newly_braked ? std::optional(EndReason::kLimit) : std::nullopt));
    }
    return started;
}

void Keepalive::brake(protocol::Axes speed, const std::vector<std::string>& braked) {
    if (!motion_) {
        return;
    }
    motion_->braked = merged(motion_->braked, braked);
    motion_->speed = speed;
    if (!moves(speed)) {
        end(EndReason::kLimit, true);
        return;
    }
    const auto now = Clock::now();
    if (send_(protocol::Control::speed_of(speed))) {
        ++frames_sent_;
    }
    motion_->next_tick = now + period_;  // the frame just sent counts as a tick
    motion_->update_pending = false;     // this event carries the latest speed
    motion_->noted = now;
    arm();
    emit_(event(MotionChange::kUpdated, EndReason::kLimit));  // last: the listener may end it
}

// The motion ends whatever happens to the zero speed: the link queues a stop
// ahead of everything else, and owes it while the device is closed.
void Keepalive::end(EndReason reason, bool send_zero) {
    if (!motion_) {
        return;
    }
    timer_.cancel();
    const auto ended = event(MotionChange::kEnded, reason);
    motion_.reset();  // before anything that could call back into us
    if (send_zero) {
        send_(protocol::Control::stop());
    }
    emit_(ended);
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
std::optional<MotionStatus> Keepalive::status() const {
    if (!motion_) {
        return std::nullopt;
    }
    const auto now = Clock::now();
    const auto left =
        std::max(Clock::duration::zero(), std::min(motion_->ends, motion_->lease_ends) - now);
    MotionStatus s{MotionMode::kSpeed, motion_->owner, motion_->speed,
                   std::chrono::duration_cast<Millis>(left)};
    s.elapsed = std::chrono::duration_cast<Millis>(now - motion_->started);
    return s;
}

void Keepalive::arm() {
    auto at = std::min({motion_->next_tick, motion_->ends, motion_->lease_ends});
    if (motion_->update_pending) {
        at = std::min(at, next_note());
    }
    timer_.expires_at(at);
    timer_.async_wait([this](boost::system::error_code ec) {
        if (!ec && motion_) {
            on_timer();
        }
    });
}

void Keepalive::on_timer() {
    const auto now = Clock::now();
    if (now >= motion_->ends) {
        end(EndReason::kDuration, true);
        return;
    }
    if (now >= motion_->lease_ends) {
        expire_();
        end(EndReason::kLeaseExpired, true);  // in case the hook left it running
        return;
    }
    if (now >= motion_->next_tick) {
        check_();  // may brake (sending at once) or end the motion
        if (!motion_) {
            return;
        }
        tick(now);
    }
    const bool note = motion_->update_pending && now >= next_note();
    if (note) {
        motion_->update_pending = false;
        motion_->noted = now;
    }
    arm();
    if (note) {
        emit_(event(MotionChange::kUpdated, std::nullopt));  // last: the listener may end it
    }
}

// Re-sends the speed, unless a frame went out since the deadline (a brake).
void Keepalive::tick(SteadyTime now) {
    if (now < motion_->next_tick) {
        return;
    }
    if (send_(protocol::Control::speed_of(motion_->speed))) {
        ++frames_sent_;
    }
    // Drift-free: from the previous deadline. A loop that stalled for
    // several periods skips the missed ticks instead of bursting them.
    do {
        motion_->next_tick += period_;
    } while (motion_->next_tick <= now);
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
