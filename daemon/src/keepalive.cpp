#include "gport/daemon/core/keepalive.hpp"

#include <algorithm>

namespace gport::daemon {

using Clock = std::chrono::steady_clock;

Keepalive::Keepalive(boost::asio::io_context& io, Millis period, Send send, Emit emit)
    : timer_(io), period_(period), send_(std::move(send)), emit_(std::move(emit)) {}

SpeedStarted Keepalive::start(const ClientInfo& owner, protocol::Axes speed, Millis duration) {
    const bool replacing = motion_.has_value();
    const auto now = Clock::now();
    motion_ = Motion{owner, speed, duration, now + duration, now + period_};
    arm();
    const auto wall_end = std::chrono::system_clock::now() + duration;
    const SpeedStarted started{duration,
                               std::chrono::time_point_cast<WallTime::duration>(wall_end)};
    // Last, and nothing of motion_ afterwards: the listener may end it
    // (its owner dropped for a full outbox) before emit_ returns.
    emit_(event(replacing ? MotionChange::kReplaced : MotionChange::kStarted, std::nullopt));
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
    timer_.expires_at(std::min(motion_->next_tick, motion_->ends));
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
    arm();
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
