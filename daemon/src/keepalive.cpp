#include "gport/daemon/core/keepalive.hpp"

#include <algorithm>

namespace gport::daemon {

using Clock = std::chrono::steady_clock;

Keepalive::Keepalive(boost::asio::io_context& io, Millis period, Send send, Emit emit)
    : timer_(io), period_(period), send_(std::move(send)), emit_(std::move(emit)) {}

namespace {

SpeedStarted started_for(Millis duration) {
    const auto wall_end = std::chrono::system_clock::now() + duration;
    return SpeedStarted{duration, std::chrono::time_point_cast<WallTime::duration>(wall_end)};
}

}  // namespace

SpeedStarted Keepalive::start(const ClientInfo& owner, protocol::Axes speed, Millis duration,
                              Millis lease) {
    if (motion_ && motion_->owner.id == owner.id) {
        return update(speed, duration, lease);
    }
    const bool replacing = motion_.has_value();
    const auto now = Clock::now();
    motion_ = Motion{owner, speed, duration, now + duration, now + period_, now + lease, now};
    arm();
    const auto started = started_for(duration);
    // Last, and nothing of motion_ afterwards: the listener may end it
    // (its owner dropped for a full outbox) before emit_ returns.
    emit_(event(replacing ? MotionChange::kReplaced : MotionChange::kStarted, std::nullopt));
    return started;
}

// The same owner's next speed: renews the end (its duration counts from now,
// as for any speed command) and the lease; published later, coalesced, unless
// the last event of the motion is older than kUpdateNoteInterval.
SpeedStarted Keepalive::update(protocol::Axes speed, Millis duration, Millis lease) {
    ++updates_;
    const auto now = Clock::now();
    motion_->speed = speed;
    motion_->duration = duration;
    motion_->ends = now + duration;
    motion_->lease_ends = now + lease;
    motion_->next_tick = now + period_;  // the frame just sent counts as a tick
    const bool note_now = now >= next_note();
    motion_->update_pending = !note_now;
    if (note_now) {
        motion_->noted = now;
    }
    arm();
    const auto started = started_for(duration);
    if (note_now) {
        emit_(event(MotionChange::kUpdated, std::nullopt));  // last, as in start()
    }
    return started;
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

std::optional<MotionStatus> Keepalive::status() const {
    if (!motion_) {
        return std::nullopt;
    }
    const auto left = std::max(Clock::duration::zero(), motion_->ends - Clock::now());
    return MotionStatus{MotionMode::kSpeed, motion_->owner, motion_->speed,
                        std::chrono::duration_cast<Millis>(left)};
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
        end(EndReason::kLeaseExpired, true);
        return;
    }
    if (now >= motion_->next_tick) {
        if (send_(protocol::Control::speed_of(motion_->speed))) {
            ++frames_sent_;
        }
        // Drift-free: from the previous deadline. A loop that stalled for
        // several periods skips the missed ticks instead of bursting them.
        do {
            motion_->next_tick += period_;
        } while (motion_->next_tick <= now);
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

MotionEvent Keepalive::event(MotionChange change, std::optional<EndReason> reason) const {
    MotionEvent e;
    e.change = change;
    e.mode = MotionMode::kSpeed;
    e.owner = motion_->owner;
    e.speed = motion_->speed;
    e.duration = motion_->duration;
    e.reason = reason;
    return e;
}

}  // namespace gport::daemon
