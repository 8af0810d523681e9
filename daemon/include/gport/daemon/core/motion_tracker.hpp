// Tracked angle and centre motions: they know when they are done. The
// gimbal turns to an angle (or the centre) on its own; the tracker watches
// the attitude and ends the motion with kReached once every axis's hall
// (joint) angle is within the tolerance of its target for two consecutive
// samples, with kStalled when the hall angles have made no progress towards
// the target for the stall window (a target beyond the gimbal's reach, an arm
// that is blocked: the end says where it stopped), or with kTimeout when it
// has not arrived within the timeout (nothing is sent then). Anything else that ends it (a newer
// command, stop, preemption, the waiting owner's departure, the link, shutdown) calls end().
//
// Hall angles, not IMU angles: the angle command is relative to the aircraft
// like the hall angles are, so a target is compared with what it commands.
//
// A motion started with an end callback has a waiting owner: the callback is
// posted to the loop exactly once when the motion ends, so that it never runs
// inside the call that ended the motion. The ended event is emitted at once.
//
// An angle (or centre) from the owner of the running motion of the same mode,
// when nobody waits for that motion, is an update, not a new motion (an
// autopilot or a tracker streaming targets at 50 Hz): the target is replaced
// in place, the timeout runs from the update, and arrival is judged against
// the new target once no update came for kUpdateNoteInterval (a stream's
// motion ends `reached` when the stream pauses at its target, not between two
// of its targets). Watchers get an kUpdated event at most
// once per kUpdateNoteInterval after the motion's previous event, carrying the
// latest target (coalesced, as for speed updates); updates() counts them.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "gport/daemon/api.hpp"

namespace gport::daemon {

// Pure: whether the gimbal has arrived, from the hall angles of successive
// samples. Arrived = two consecutive samples with every axis within the
// tolerance of the target; a sample outside starts the count again.
class Arrival {
  public:
    Arrival(protocol::Axes target, double tolerance_deg);

    // Offers the next sample's hall angles; true once arrived (and after).
    bool observe(const protocol::Axes& hall);
    bool arrived() const { return consecutive_ >= kSamplesNeeded; }

    // Every axis of `hall` within `tolerance` (0.01°) of `target`.
    static bool within(const protocol::Axes& hall, const protocol::Axes& target,
                       std::int32_t tolerance);

    static constexpr unsigned kSamplesNeeded = 2;

  private:
    protocol::Axes target_;
    std::int32_t tolerance_;  // 0.01°
    unsigned consecutive_ = 0;
};

// Pure: whether a motion still makes progress. Its distance is the largest
// axis's |hall − target|; progress is a new smallest distance at least kStep
// below the previous smallest, so jitter around a stop is none. No progress
// within the window after the start or the last progress: stalled.
class Progress {
  public:
    Progress(protocol::Axes target, SteadyTime since, Millis window)
        : target_(target), since_(since), window_(window) {}

    // Offers a sample's hall angles received at `now`; true once no progress
    // came for the window (a zero window: never).
    bool stalled(const protocol::Axes& hall, SteadyTime now);
    Millis window() const { return window_; }
    // Where it stopped: "pitch -90.00 (target -100.00, 10.00° short)", the
    // axis farthest from its target in the last sample offered.
    std::string where() const;

    static constexpr std::int32_t kStep = 10;  // 0.1°, in 0.01°

  private:
    protocol::Axes target_;
    SteadyTime since_;  // the start, or the last progress
    Millis window_;
    std::optional<std::int32_t> best_;
    protocol::Axes last_{};
};

class MotionTracker {
  public:
    using Emit = std::function<void(const MotionEvent&)>;

    struct Options {
        double tolerance_deg = 0.5;
        Millis timeout{10000};
        Millis stall{2000};  // zero: no stall detection
    };

    static constexpr Millis kUpdateNoteInterval{500};

    // `latest`: the newest attitude sample (Core's, the one copy gportd keeps),
    // which a motion's end reports to its waiter.
    MotionTracker(boost::asio::io_context& io, Options options, Emit emit,
                  const std::optional<AttitudeSample>& latest);

    // For motions started from now on; a running motion keeps its own.
    void set_options(Options options) { options_ = options; }

    // Starts tracking `target` (0.01°; centre: 0) for `owner`; a running
    // motion first ends with kReplaced, unless this is an update of it (see
    // above). `on_end` empty: nobody waits. `clamped`: the target's axes the
    // soft limits clamped (told in the motion's events).
    void start(const ClientInfo& owner, MotionMode mode, protocol::Axes target,
               MotionEndCallback on_end = {}, std::vector<std::string> clamped = {});
    // Offers every attitude sample, once `latest` is it; may end the motion
    // with kReached or kStalled.
    void on_attitude(const AttitudeSample& sample);
    // Ends the motion, if any, with `reason` (`detail`: see MotionEnd). Emits last.
    void end(EndReason reason, std::string detail = {});

    bool active() const { return motion_.has_value(); }
    bool waiting() const { return motion_ && static_cast<bool>(motion_->on_end); }
    std::optional<ClientInfo> owner() const;
    std::optional<MotionStatus> status() const;
    // Angle and centre commands that updated their owner's running motion.
    std::uint64_t updates() const { return updates_; }

  private:
    struct Motion {
        ClientInfo owner;
        MotionMode mode;
        protocol::Axes target;
        SteadyTime started;
        SteadyTime commanded;  // the last start or update: the timeout runs from it
        Arrival arrival;
        Progress progress;
        MotionEndCallback on_end;
        SteadyTime noted;             // when the last event of this motion went out
        bool update_pending = false;  // an update not yet published
        std::vector<std::string> clamped{};
        bool updated = false;  // a stream: arrival waits for it to settle
    };

    bool is_update(const ClientInfo& owner, MotionMode mode) const;
    void update(protocol::Axes target, MotionEndCallback on_end, std::vector<std::string> clamped);
    void note_update();
    MotionEvent event(MotionChange change, std::optional<EndReason> reason,
                      std::string detail = {}) const;
    void arm();

    boost::asio::io_context& io_;
    boost::asio::steady_timer timer_;
    boost::asio::steady_timer note_timer_;  // publishes a coalesced update
    Options options_;
    Emit emit_;
    std::optional<Motion> motion_;
    const std::optional<AttitudeSample>& latest_;
    std::uint64_t updates_ = 0;
};

}  // namespace gport::daemon
