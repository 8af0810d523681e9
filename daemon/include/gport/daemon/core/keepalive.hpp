// The speed keepalive and deadman. A speed command goes out at once and is
// re-sent at the keepalive rate until its duration ends; then, or on stop,
// when its owner goes away, on shutdown or when the link drops, the motion
// ends. Every tick's deadline is computed from the previous deadline, not
// from "now", so the period does not drift.
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

    Keepalive(boost::asio::io_context& io, Millis period, Send send, Emit emit);

    // Starts (or replaces) the motion; the first frame has already been sent.
    // Both start() and end() emit last, so the listener may call back in.
    SpeedStarted start(const ClientInfo& owner, protocol::Axes speed, Millis duration);
    // Ends the motion, if any, with the reason; sends zero speed if asked.
    void end(EndReason reason, bool send_zero);

    bool active() const { return motion_.has_value(); }
    std::optional<ClientInfo> owner() const;
    std::optional<MotionStatus> status() const;
    std::uint64_t frames_sent() const { return frames_sent_; }

  private:
    struct Motion {
        ClientInfo owner;
        protocol::Axes speed;
        Millis duration;
        SteadyTime ends;
        SteadyTime next_tick;
    };

    void arm();
    void on_timer();
    MotionEvent event(MotionChange change, std::optional<EndReason> reason) const;

    boost::asio::steady_timer timer_;
    Millis period_;
    Send send_;
    Emit emit_;
    std::optional<Motion> motion_;
    std::uint64_t frames_sent_ = 0;
};

}  // namespace gport::daemon
