#include "gport/daemon/core/motion_tracker.hpp"

#include <boost/asio/post.hpp>
#include <cmath>
#include <cstdlib>
#include <utility>

namespace gport::daemon {

using Clock = std::chrono::steady_clock;

// ---- Arrival -------------------------------------------------------------------

Arrival::Arrival(protocol::Axes target, double tolerance_deg)
    : target_(target), tolerance_(static_cast<std::int32_t>(std::lround(tolerance_deg * 100))) {}

bool Arrival::within(const protocol::Axes& hall, const protocol::Axes& target,
                     std::int32_t tolerance) {
    const auto close = [tolerance](std::int16_t a, std::int16_t b) {
        return std::abs(std::int32_t{a} - std::int32_t{b}) <= tolerance;
    };
    return close(hall.roll, target.roll) && close(hall.pitch, target.pitch) &&
           close(hall.yaw, target.yaw);
}

bool Arrival::observe(const protocol::Axes& hall) {
    if (arrived()) {
        return true;
    }
    consecutive_ = within(hall, target_, tolerance_) ? consecutive_ + 1 : 0;
    return arrived();
}

// ---- MotionTracker -------------------------------------------------------------

MotionTracker::MotionTracker(boost::asio::io_context& io, Options options, Emit emit)
    : io_(io), timer_(io), options_(options), emit_(std::move(emit)) {}

void MotionTracker::start(const ClientInfo& owner, MotionMode mode, protocol::Axes target,
                          MotionEndCallback on_end) {
    end(EndReason::kReplaced);
    motion_ = Motion{owner,
                     mode,
                     target,
                     Clock::now(),
                     Arrival(target, options_.tolerance_deg),
                     std::move(on_end)};
    arm();
    // Last, and nothing of motion_ afterwards: the listener may end it.
    emit_(event(MotionChange::kStarted, std::nullopt));
}

void MotionTracker::arm() {
    timer_.expires_at(motion_->started + options_.timeout);
    timer_.async_wait([this](boost::system::error_code ec) {
        if (!ec && motion_ && Clock::now() >= motion_->started + options_.timeout) {
            end(EndReason::kTimeout);
        }
    });
}

void MotionTracker::on_attitude(const AttitudeSample& sample) {
    latest_ = sample;
    if (motion_ && motion_->arrival.observe(sample.attitude.hall)) {
        end(EndReason::kReached);
    }
}

// The motion is gone before anything is told of its end, so that a listener
// may start another.
void MotionTracker::end(EndReason reason) {
    if (!motion_) {
        return;
    }
    timer_.cancel();
    const auto ended = event(MotionChange::kEnded, reason);
    auto on_end = std::move(motion_->on_end);
    const auto elapsed = std::chrono::duration_cast<Millis>(Clock::now() - motion_->started);
    motion_.reset();
    if (on_end) {
        boost::asio::post(io_, [on_end = std::move(on_end),
                                result = MotionEnd{reason, latest_, elapsed}] { on_end(result); });
    }
    emit_(ended);
}

std::optional<ClientInfo> MotionTracker::owner() const {
    if (!motion_) {
        return std::nullopt;
    }
    return motion_->owner;
}

std::optional<MotionStatus> MotionTracker::status() const {
    if (!motion_) {
        return std::nullopt;
    }
    MotionStatus s;
    s.mode = motion_->mode;
    s.owner = motion_->owner;
    s.target = motion_->target;
    s.elapsed = std::chrono::duration_cast<Millis>(Clock::now() - motion_->started);
    return s;
}

MotionEvent MotionTracker::event(MotionChange change, std::optional<EndReason> reason) const {
    MotionEvent e;
    e.change = change;
    e.mode = motion_->mode;
    e.owner = motion_->owner;
    e.angle = motion_->target;
    e.reason = reason;
    return e;
}

}  // namespace gport::daemon
