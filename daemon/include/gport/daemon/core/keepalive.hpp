// The running speed motion and its schedule. A speed command goes out at
// once and is re-sent at the keepalive rate until its duration ends; then,
// or on stop, when its owner goes away, on shutdown or when the link drops,
// the motion ends. Every tick's deadline is computed from the previous
// deadline, not from "now", so the period does not drift.
//
// A speed from the motion's own owner (a joystick streaming commands) is an
// update, not a new motion: the speed, end and lease are renewed, and an
// kUpdated event goes out at most once per kUpdateNoteInterval after the
// previous event of the motion, carrying the latest speed. The lease is the
// deadman for a controller that hangs with its socket open: when no update
// comes within it, the motion is due to end (kLeaseEnd; Motion applies the
// failsafe, which ends it with kLeaseExpired).
//
// State only: no timer, no I/O. Motion (motion.hpp) owns the timer, asks
// due() what a wake-up is for, sends the frames and publishes the events
// this returns.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "gport/daemon/api.hpp"

namespace gport::daemon {

class Keepalive {
  public:
    static constexpr Millis kUpdateNoteInterval{500};

    // What start() did: the figures for the reply, and the event to publish
    // (none for an update that is published later, coalesced).
    struct Started {
        SpeedStarted reply;
        std::optional<MotionEvent> event;
    };

    // What a wake-up at a moment is for, the first that applies.
    enum class Due { kNothing, kEnd, kLeaseEnd, kTick };

    explicit Keepalive(Millis period) : period_(period) {}

    // Starts, replaces or (same owner) updates the motion at `now`; its first
    // frame has already been sent. It ends after `duration`, or after
    // `lease` without another start() by its owner. `braked`: the axes the
    // soft limits zeroed in `speed`; an update that brakes an axis not braked
    // before is published at once (kUpdated, reason kLimit).
    Started start(const ClientInfo& owner, protocol::Axes speed, Millis duration, Millis lease,
                  std::vector<std::string> braked, SteadyTime now);
    // The soft limits zeroed `braked` in the running motion's speed, giving
    // `speed`. While an axis is left moving: `speed` goes out now (it counts
    // as a tick) and this returns its kUpdated event (reason kLimit); none
    // when nothing is left moving (the motion is to end with kLimit).
    std::optional<MotionEvent> brake(protocol::Axes speed, const std::vector<std::string>& braked,
                                     SteadyTime now);
    // Ends the motion with `reason`; its kEnded event, none when none ran.
    std::optional<MotionEvent> end(EndReason reason);

    Due due(SteadyTime now) const;
    // The speed to re-send at a due tick, unless a frame went out since the
    // deadline (a brake); moves the deadline on.
    std::optional<protocol::Axes> tick(SteadyTime now);
    // The coalesced update, once it is due (at most one per interval).
    std::optional<MotionEvent> note(SteadyTime now);
    // When the next thing is due; only while active().
    SteadyTime wake_at() const;

    bool active() const { return motion_.has_value(); }
    std::optional<ClientInfo> owner() const;
    std::optional<protocol::Axes> speed() const;
    std::optional<MotionStatus> status(SteadyTime now) const;
    Millis period() const { return period_; }
    std::uint64_t updates() const { return updates_; }

  private:
    struct Motion {
        ClientInfo owner;
        protocol::Axes speed;
        Millis duration;
        SteadyTime started;
        SteadyTime ends;
        SteadyTime next_tick;
        SteadyTime lease_ends;
        SteadyTime noted;                   // when the last event of this motion went out
        bool update_pending = false;        // an update not yet published
        std::vector<std::string> braked{};  // axes the soft limits hold at zero
    };

    Started update(protocol::Axes speed, Millis duration, Millis lease,
                   std::vector<std::string> braked, SteadyTime now);
    SteadyTime next_note() const { return motion_->noted + kUpdateNoteInterval; }
    MotionEvent event(MotionChange change, std::optional<EndReason> reason) const;

    Millis period_;
    std::optional<Motion> motion_;
    std::uint64_t updates_ = 0;
};

}  // namespace gport::daemon
