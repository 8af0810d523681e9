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
// deadman for a controller that hangs with its socket open: when no update
// comes within it, the Expire hook is called (the core applies the failsafe,
// which ends the motion with kLeaseExpired).
//
// Braking at the soft limits (soft_brake.hpp) is the core's: the Check hook
// runs on every tick before the speed is re-sent, and brake() zeroes axes
// of the running motion.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "gport/daemon/api.hpp"

namespace gport::daemon {

class Keepalive {
  public:
    // Puts a control frame on the wire; false when it could not be queued.
    using Send = std::function<bool(const protocol::Control&)>;
    using Emit = std::function<void(const MotionEvent&)>;
    // Called before a tick re-sends the speed (may brake or end the motion),
    // and when the lease runs out (must end the motion).
    using Check = std::function<void()>;
    using Expire = std::function<void()>;

    static constexpr Millis kUpdateNoteInterval{500};

    Keepalive(boost::asio::io_context& io, Millis period, Send send, Emit emit, Check check,
              Expire expire);

    // Starts, replaces or (same owner) updates the motion; the first frame has
    // already been sent. It ends after `duration`, or after `lease` without
    // another start() by its owner. `braked`: the axes the soft limits
    // zeroed in `speed`; an update that brakes an axis not braked before is
    // published at once (kUpdated, reason kLimit). Both start() and end()
    // emit last, so the listener may call back in.
    SpeedStarted start(const ClientInfo& owner, protocol::Axes speed, Millis duration, Millis lease,
                       std::vector<std::string> braked = {});
    // Ends the motion, if any, with the reason; sends zero speed if asked.
    void end(EndReason reason, bool send_zero);
    // The soft limits zeroed `braked` in the running motion's speed, giving
    // `speed`: sends it at once and publishes kUpdated (reason kLimit), or
    // ends the motion (kLimit, zero speed) when no axis is left moving.
    void brake(protocol::Axes speed, const std::vector<std::string>& braked);

    bool active() const { return motion_.has_value(); }
    std::optional<ClientInfo> owner() const;
    std::optional<protocol::Axes> speed() const;
    std::optional<MotionStatus> status() const;
    Millis period() const { return period_; }
    std::uint64_t frames_sent() const { return frames_sent_; }
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

    SpeedStarted update(protocol::Axes speed, Millis duration, Millis lease,
                        std::vector<std::string> braked);
    SteadyTime next_note() const { return motion_->noted + kUpdateNoteInterval; }

    void arm();
    void on_timer();
    void tick(SteadyTime now);
    MotionEvent event(MotionChange change, std::optional<EndReason> reason) const;

    boost::asio::steady_timer timer_;
    Millis period_;
    Send send_;
    Emit emit_;
    Check check_;
    Expire expire_;
    std::optional<Motion> motion_;
    std::uint64_t frames_sent_ = 0;
    std::uint64_t updates_ = 0;
};

}  // namespace gport::daemon
