// The speed keepalive and deadman. A speed command goes out at once and is
// re-sent at the keepalive rate until its duration ends; then, or on stop,
// when its owner goes away, on shutdown or when the link drops, the motion
// ends. Every tick's deadline is computed from the previous deadline, not
// from "now", so the period does not drift.
//
// A speed from the motion's own owner (a joystick streaming commands) is an
// update, not a new motion: the speed, end and lease are renewed, and an
// kUpdated event goes out at most once per kUpdateNoteInterval after the
// previous event of the motion, carrying the latest speed. The lease is the
// deadman for a controller that hangs with its socket open: no update within
// it ends the motion with kLeaseExpired and a zero speed.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <functional>
#include <optional>

#include "gport/daemon/api.hpp"

namespace gport::daemon {

class Keepalive {
  public:
    // Puts a control frame on the wire; false when it could not be queued.
    using Send = std::function<bool(const protocol::Control&)>;
    using Emit = std::function<void(const MotionEvent&)>;

    static constexpr Millis kUpdateNoteInterval{500};

    Keepalive(boost::asio::io_context& io, Millis period, Send send, Emit emit);

    // Starts, replaces or (same owner) updates the motion; the first frame has
    // already been sent. It ends after `duration`, or after `lease` without
    // another start() by its owner. Both start() and end() emit last, so the
    // listener may call back in.
    SpeedStarted start(const ClientInfo& owner, protocol::Axes speed, Millis duration,
                       Millis lease);
    // Ends the motion, if any, with the reason; sends zero speed if asked.
    void end(EndReason reason, bool send_zero);

    bool active() const { return motion_.has_value(); }
    std::optional<ClientInfo> owner() const;
    std::optional<MotionStatus> status() const;
    std::uint64_t frames_sent() const { return frames_sent_; }
    std::uint64_t updates() const { return updates_; }

  private:
    struct Motion {
        ClientInfo owner;
        protocol::Axes speed;
        Millis duration;
        SteadyTime ends;
        SteadyTime next_tick;
        SteadyTime lease_ends;
        SteadyTime noted;             // when the last event of this motion went out
        bool update_pending = false;  // an update not yet published
    };

    SpeedStarted update(protocol::Axes speed, Millis duration, Millis lease);
    SteadyTime next_note() const { return motion_->noted + kUpdateNoteInterval; }

    void arm();
    void on_timer();
    MotionEvent event(MotionChange change, std::optional<EndReason> reason) const;

    boost::asio::steady_timer timer_;
    Millis period_;
    Send send_;
    Emit emit_;
    std::optional<Motion> motion_;
    std::uint64_t frames_sent_ = 0;
    std::uint64_t updates_ = 0;
};

}  // namespace gport::daemon
