// gport::daemon::Motion — the motion policy: what moves the gimbal, and what
// ends it. One owner for the running motion (a speed motion, kept alive by
// the Keepalive schedule and its timer, or a tracked angle or centre motion,
// MotionTracker), the soft limits on commands (MotionLimits), braking at
// them by the attitude (SoftBrake) and the failsafe policies. Core keeps the
// link, the settings, arbitration and status: it checks who may command,
// then hands the command here; it tells this of every attitude sample and
// link change, and of owners leaving.
//
// Commands come in two steps with Core's admission between them, so that a
// bad parameter is refused before access and control are (docs/api.md):
// check_speed() / check_angle(), then speed() / angle() / center() /
// lock(). The frames go through the GimbalLink, as every frame does; motion events
// are logged here and go to the observer.
//
// Freshness — one rule, for braking, for the hold failsafe and for ending a
// motion that brakes by the attitude: a sample is fresh while it is younger
// than link.stale_ms (docs/api.md: "no attitude younger than
// `link.stale_ms`"). A sample exactly link.stale_ms old is stale, as it is
// for the link state (LinkMonitor reports `stale` at that instant).
#pragma once

#include <spdlog/logger.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gport/config/config.hpp"
#include "gport/daemon/api.hpp"
#include "gport/daemon/core/gimbal_link.hpp"
#include "gport/daemon/core/keepalive.hpp"
#include "gport/daemon/core/motion_limits.hpp"
#include "gport/daemon/core/motion_tracker.hpp"
#include "gport/daemon/core/soft_brake.hpp"

namespace gport::daemon {

// The one freshness rule: true while a sample `age` old is younger than
// `stale_after` (link.stale_ms).
constexpr bool is_fresh(Millis age, Millis stale_after) {
    return age < stale_after;
}

// A speed command's parameters after the checks: the speed within the soft
// limits (and the axes clamped to limits.max_speed), its duration and lease.
struct SpeedRequest {
    Limited speed;
    Millis duration;
    Millis lease;
};

class Motion {
  public:
    // `latest`: the newest attitude sample, Core's (the one copy gportd
    // keeps), up to date before on_attitude is called.
    Motion(boost::asio::io_context& io, const config::Config& config, GimbalLink& link,
           std::shared_ptr<spdlog::logger> log, const std::optional<AttitudeSample>& latest);
    Motion(const Motion&) = delete;
    Motion& operator=(const Motion&) = delete;

    void set_observer(CoreObserver* observer) { observer_ = observer; }
    // SIGHUP: the default and longest speed durations, the soft limits, the
    // failsafe policies (applied to a running motion when it ends) and the
    // motion tolerance and timeout (for motions started afterwards).
    void reload(const config::Config& config);
    const config::LimitsConfig& limits() const { return limits_; }
    Millis max_duration() const { return durations_.max_duration; }

    // ---- commands: check, then (once Core admitted the client) act ----
    // kInvalidParams for a duration or lease out of 1..max_duration, or a
    // speed beyond limits.max_speed without `clamp`.
    Outcome<SpeedRequest> check_speed(protocol::Axes speed, std::optional<Millis> duration,
                                      bool clamp, std::optional<Millis> lease) const;
    // Brakes the speed at the soft limits (kLinkDown when that needs a fresh
    // attitude and there is none), sends it, and starts, updates or
    // replaces the speed motion (ending a tracked one).
    Outcome<SpeedStarted> speed(const ClientInfo& client, SpeedRequest request);
    Outcome<Limited> check_angle(protocol::Axes angle, bool clamp) const;
    // The centre (0/0/0) clamped into the soft limits.
    Limited center_target() const { return MotionLimits(limits_).center_target(); }
    // angle and centre become tracked motions (a newer one replaces the
    // running one: kReplaced); lock ends any motion (kSuperseded) and is not
    // tracked: it has no target.
    Outcome<AngleSent> angle(const ClientInfo& client, Limited target, MotionEndCallback on_end);
    Outcome<AngleSent> center(const ClientInfo& client, MotionEndCallback on_end);
    Outcome<Done> lock(const ClientInfo& client);
    // Zero speed, and the running motion (if any) ends with kStop. False
    // when the zero speed could not be queued (it is owed to the device).
    bool stop();

    // ---- what ends a motion from outside ----
    // The deadman: `client` is gone; the failsafe applies to a speed motion
    // it owns or a tracked one it waits for (a tracked motion nobody waits
    // for was a completed command: it runs on).
    void owner_gone(const ClientInfo& client);
    // Another client took control: the motion ends, zero speed first.
    void preempt();
    // gportd stops: failsafe.on_shutdown.
    void shutdown();
    // down: the motion ends (failsafe.on_link_lost; nothing can be sent);
    // stale: a speed motion that brakes by the attitude ends (no_attitude).
    void on_link(LinkState state);
    // Every sample (`latest` is it), before it is published: braking reacts
    // to each one.
    void on_attitude();
    // Every sample, once published: the tracker may end a motion (reached),
    // which watchers hear of after the sample itself.
    void on_attitude_published(const AttitudeSample& sample);

    // ---- figures ----
    std::optional<ClientInfo> owner() const;
    std::optional<MotionStatus> status() const;
    std::uint64_t keepalive_frames() const { return keepalive_frames_; }
    std::uint64_t updates() const { return keepalive_.updates() + tracker_.updates(); }

  private:
    // The latest sample at `now`: its age (none when no sample arrived)
    // and whether it is fresh (is_fresh, the one rule).
    struct Freshness {
        std::optional<Millis> age;
        bool fresh = false;
    };
    Freshness freshness(SteadyTime now) const;
    SoftBrake soft_brake() const { return SoftBrake(limits_, keepalive_.period()); }
    // A speed after braking; kLinkDown when an axis it moves needs a fresh
    // attitude and there is none.
    Outcome<Braked> brake_command(protocol::Axes speed) const;
    // A speed command whose every moving axis was braked: nothing moves.
    SpeedStarted stopped_at_limit(const ClientInfo& client, const Braked& braked);
    Outcome<Done> position(const ClientInfo& client, const protocol::Control& control,
                           std::optional<MotionMode> track_as, MotionEndCallback on_end = {},
                           std::vector<std::string> clamped = {});
    // The centre command, or the angle frame to the centre clamped into the
    // soft limits.
    static protocol::Control center_control(const Limited& target);

    // The keepalive: its timer, a tick, and braking the running speed.
    void arm_keepalive();
    void on_keepalive_timer();
    // On every attitude sample, keepalive tick and stale link: brakes the
    // running speed motion's axes near their limits, or ends it
    // (kNoAttitude) when it needs an attitude that is not fresh.
    void watch_speed(SteadyTime now);
    void brake_speed(const Braked& braked);
    void send_keepalive(protocol::Axes speed);

    // Ends the motion (speed or tracked), if any, for `reason` under the
    // failsafe `policy`: zero speed first (if `send_zero`), then the hold
    // angle or the centre frame; logs the action once at warning level.
    void failsafe(EndReason reason, config::Failsafe policy, bool send_zero);
    // The hold or centre frame a failsafe sends after the zero speed (none
    // for stop, or a hold without a fresh attitude); `note` says what.
    std::optional<protocol::Control> failsafe_frame(config::Failsafe& action,
                                                    std::string& note) const;
    // Ends whichever motion runs; zero speed first if `send_zero`.
    void end(EndReason reason, bool send_zero);
    void end_speed(EndReason reason, bool send_zero);
    bool send(const protocol::Control& control);
    // Logs a motion event and tells the observer.
    void publish(const MotionEvent& event);

    config::KeepaliveConfig durations_;  // rate_hz is fixed at start
    config::LimitsConfig limits_;
    config::FailsafeConfig failsafe_;
    Millis stale_after_;
    GimbalLink& link_;
    std::shared_ptr<spdlog::logger> log_;
    CoreObserver* observer_ = nullptr;
    const std::optional<AttitudeSample>& latest_;
    Keepalive keepalive_;  // the speed motion
    boost::asio::steady_timer keepalive_timer_;
    MotionTracker tracker_;  // angle and centre motions; at most one of the two runs
    std::uint64_t keepalive_frames_ = 0;
};

}  // namespace gport::daemon
