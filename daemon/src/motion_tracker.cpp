#include "gport/daemon/core/motion_tracker.hpp"

#include <fmt/format.h>

#include <array>
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

// ---- Progress ------------------------------------------------------------------

namespace {

constexpr std::array<const char*, 3> kAxisNames{"roll", "pitch", "yaw"};

std::array<std::int32_t, 3> offsets(const protocol::Axes& hall, const protocol::Axes& target) {
    return {std::int32_t{hall.roll} - target.roll, std::int32_t{hall.pitch} - target.pitch,
            std::int32_t{hall.yaw} - target.yaw};
}

std::size_t farthest(const std::array<std::int32_t, 3>& off) {
    std::size_t axis = 0;
    for (std::size_t i = 1; i < off.size(); ++i) {
        if (std::abs(off[i]) > std::abs(off[axis])) {
            axis = i;
        }
    }
    return axis;
}

}  // namespace

bool Progress::stalled(const protocol::Axes& hall, SteadyTime now) {
    last_ = hall;
    const auto off = offsets(hall, target_);
    const auto distance = std::abs(off[farthest(off)]);
    if (!best_ || distance <= *best_ - kStep) {
        best_ = distance;
        since_ = now;
        return false;
    }
    return window_.count() > 0 && now - since_ >= window_;
}

std::string Progress::where() const {
    const auto off = offsets(last_, target_);
    const auto axis = farthest(off);
    const std::array<std::int32_t, 3> at{last_.roll, last_.pitch, last_.yaw};
    return fmt::format("{} {:.2f} (target {:.2f}, {:.2f}° short)", kAxisNames[axis],
                       at[axis] / 100.0, (at[axis] - off[axis]) / 100.0,
                       std::abs(off[axis]) / 100.0);
}

// ---- MotionTracker -------------------------------------------------------------

MotionTracker::MotionTracker(boost::asio::io_context& io, Options options, Emit emit,
                             const std::optional<AttitudeSample>& latest)
    : io_(io),
      timer_(io),
      note_timer_(io),
      options_(options),
      emit_(std::move(emit)),
      latest_(latest) {}

void MotionTracker::start(const ClientInfo& owner, MotionMode mode, protocol::Axes target,
                          MotionEndCallback on_end, std::vector<std::string> clamped) {
    if (is_update(owner, mode)) {
        update(target, std::move(on_end), std::move(clamped));
        return;
    }
    end(EndReason::kReplaced);
    const auto now = Clock::now();
    motion_ = Motion{owner,
                     mode,
                     target,
                     now,
                     now,
                     Arrival(target, options_.tolerance_deg),
                     Progress(target, now, options_.stall),
                     std::move(on_end),
                     now,
                     false,
                     std::move(clamped)};
    arm();
    // Last, and nothing of motion_ afterwards: the listener may end it.
    emit_(event(MotionChange::kStarted, std::nullopt));
}

// A waiting owner is owed the outcome of the motion it waits for, so a
// motion somebody waits for is always replaced, never updated.
bool MotionTracker::is_update(const ClientInfo& owner, MotionMode mode) const {
    return motion_ && motion_->owner.id == owner.id && motion_->mode == mode && !motion_->on_end;
}

// Published at once when the motion's last event is older than
// kUpdateNoteInterval, else once that interval is over (coalesced: the event
// carries the target of the latest update).
void MotionTracker::update(protocol::Axes target, MotionEndCallback on_end,
                           std::vector<std::string> clamped) {
    ++updates_;
    const auto now = Clock::now();
    motion_->target = target;
    motion_->clamped = std::move(clamped);
    motion_->updated = true;
    motion_->commanded = now;
    motion_->arrival = Arrival(target, options_.tolerance_deg);
    motion_->progress = Progress(target, now, options_.stall);
    motion_->on_end = std::move(on_end);
    arm();
    if (now >= motion_->noted + kUpdateNoteInterval) {
        note_update();
        return;
    }
    if (!motion_->update_pending) {
        motion_->update_pending = true;
        note_timer_.expires_at(motion_->noted + kUpdateNoteInterval);
        note_timer_.async_wait([this](boost::system::error_code ec) {
            if (!ec && motion_ && motion_->update_pending) {
                note_update();
            }
        });
    }
}

void MotionTracker::note_update() {
    motion_->update_pending = false;
    motion_->noted = Clock::now();
    emit_(event(MotionChange::kUpdated, std::nullopt));  // last: the listener may end it
}

void MotionTracker::arm() {
    timer_.expires_at(motion_->commanded + options_.timeout);
    timer_.async_wait([this](boost::system::error_code ec) {
        if (!ec && motion_ && Clock::now() >= motion_->commanded + options_.timeout) {
            end(EndReason::kTimeout);
        }
    });
}

void MotionTracker::on_attitude(const AttitudeSample& sample) {
    if (!motion_) {
        return;
    }
    const bool settled =
        !motion_->updated || sample.received >= motion_->commanded + kUpdateNoteInterval;
    if (settled && motion_->arrival.observe(sample.attitude.hall)) {
        end(EndReason::kReached);
    } else if (motion_->progress.stalled(sample.attitude.hall, sample.received)) {
        end(EndReason::kStalled,
            fmt::format("stalled at {}: no progress for {} ms; beyond the gimbal's reach, or "
                        "blocked?",
                        motion_->progress.where(), motion_->progress.window().count()));
    }
}

// The motion is gone before anything is told of its end, so that a listener
// may start another.
void MotionTracker::end(EndReason reason, std::string detail) {
    if (!motion_) {
        return;
    }
    timer_.cancel();
    note_timer_.cancel();  // the ended event carries the latest target
    const auto ended = event(MotionChange::kEnded, reason, detail);
    auto on_end = std::move(motion_->on_end);
    const auto elapsed = std::chrono::duration_cast<Millis>(Clock::now() - motion_->started);
    motion_.reset();
    if (on_end) {
        boost::asio::post(io_, [on_end = std::move(on_end),
                                result = MotionEnd{reason, latest_, elapsed, std::move(detail)}] {
            on_end(result);
        });
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

MotionEvent MotionTracker::event(MotionChange change, std::optional<EndReason> reason,
                                 std::string detail) const {
    MotionEvent e;
    e.change = change;
    e.mode = motion_->mode;
    e.owner = motion_->owner;
    e.angle = motion_->target;
    e.reason = reason;
    e.clamped = motion_->clamped;
    e.detail = std::move(detail);
    return e;
}

}  // namespace gport::daemon
