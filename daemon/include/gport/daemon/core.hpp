// gport::daemon::Core — the one object that owns the gimbal device and keeps
// it safe for every client: the serial port with reconnect, link health, the
// speed keepalive and deadman, settings requests, control arbitration,
// counters. Clients see it only as a daemon::Api; the program that runs
// gportd constructs it, and so sees its parts (gport/daemon/core/).
#pragma once

#include <spdlog/logger.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "gport/config/config.hpp"
#include "gport/daemon/api.hpp"
#include "gport/daemon/core/arbiter.hpp"
#include "gport/daemon/core/keepalive.hpp"
#include "gport/daemon/core/link_monitor.hpp"
#include "gport/daemon/core/motion_limits.hpp"
#include "gport/daemon/core/motion_tracker.hpp"
#include "gport/daemon/core/serial_port.hpp"
#include "gport/daemon/core/settings_exchange.hpp"
#include "gport/daemon/core/soft_brake.hpp"
#include "gport/protocol/decoder.hpp"

namespace gport::daemon {

class Core final : public Api {
  public:
    Core(boost::asio::io_context& io, const config::Config& config,
         std::shared_ptr<spdlog::logger> log);
    ~Core() override = default;
    Core(const Core&) = delete;
    Core& operator=(const Core&) = delete;

    // Opens the device (retrying forever in the background) and starts timers.
    void start();
    // Stops any running motion with a zero-speed frame (then the
    // failsafe.on_shutdown frame, if any), waits (bounded) for it
    // to reach the device, closes the device, then calls done.
    void shutdown(std::function<void()> done);
    // SIGHUP: applies the keys that may change at run time — who may command
    // (a fresh access policy, so no cached decision survives) and the default
    // and longest speed durations, the soft limits, the failsafe policies
    // (which apply to a running motion when it ends) and the motion tolerance
    // and timeout (for motions started afterwards). A running motion is
    // otherwise left as it is.
    void reload(const config::Config& config);
    // Also told of every link change (e.g. for the service manager's status).
    void add_link_listener(std::function<void(const LinkEvent&)> listener);

    // ---- Api (core_commands.cpp, core_status.cpp) ----
    void set_observer(CoreObserver* observer) override { observer_ = observer; }
    Status status() const override;
    std::optional<AttitudeSample> latest_attitude() const override { return latest_; }
    bool may_command(const ClientInfo& client) const override;
    config::LimitsConfig limits() const override { return config_.limits; }
    Millis max_duration() const override { return config_.keepalive.max_duration; }
    Outcome<SpeedStarted> speed(const ClientInfo& client, protocol::Axes speed,
                                std::optional<Millis> duration, bool clamp = false,
                                std::optional<Millis> lease = std::nullopt) override;
    Outcome<Done> stop(const ClientInfo& client) override;
    Outcome<AngleSent> angle(const ClientInfo& client, protocol::Axes angle, bool clamp = false,
                             MotionEndCallback on_end = {}) override;
    Outcome<AngleSent> center(const ClientInfo& client, MotionEndCallback on_end = {}) override;
    Outcome<Done> lock(const ClientInfo& client) override;
    Outcome<Done> photo(const ClientInfo& client) override;
    Outcome<RecordResult> record(const ClientInfo& client, RecordRequest request) override;
    Outcome<std::optional<ClientInfo>> acquire(const ClientInfo& client) override;
    Outcome<std::optional<ClientInfo>> release(const ClientInfo& client) override;
    void get_settings(const ClientInfo& client, SettingsCallback done) override;
    void set_settings(const ClientInfo& client, SettingsChange change,
                      SettingsCallback done) override;
    void client_gone(const ClientInfo& client) override;
    void client_closed(const ClientInfo& client) override;

  private:
    // ---- commands (core_commands.cpp) ----
    // The checks a command passes after its parameters, in the order api.hpp
    // states: access and control (Arbiter), then the device.
    std::optional<CommandError> admit(const ClientInfo& client, Arbiter::Needs needs) const;
    bool device_ready() const { return port_.is_open() && !stopping_; }
    // The one kLinkDown error: names the device and why nothing goes to it,
    // then what follows for this request (may be empty).
    CommandError link_down(std::string_view consequence = {}) const;
    // Sends a position frame (angle, centre or lock) and, when `track_as` is
    // given, tracks it as a motion of that mode towards the frame's angle
    // (`clamped`: the axes the soft limits clamped, told in its events).
    Outcome<Done> position(const ClientInfo& client, const protocol::Control& control,
                           std::optional<MotionMode> track_as, MotionEndCallback on_end = {},
                           std::vector<std::string> clamped = {});
    // The centre command, or the angle frame to the centre clamped into the
    // soft limits.
    protocol::Control centre_control(const Limited& centre) const;
    Outcome<Done> camera(const ClientInfo& client, protocol::CameraAction action);
    void settings(const ClientInfo& client, std::optional<SettingsChange> change,
                  SettingsCallback done);
    bool send(const protocol::Frame& frame);
    bool send_control(const protocol::Control& control);
    // Ends the motion (speed or tracked), if any, for `reason` under the
    // failsafe `policy`: zero speed first (if `send_zero`), then the hold
    // angle or the centre frame; logs the action once at warning level.
    void failsafe_end(EndReason reason, config::Failsafe policy, bool send_zero);
    // The owner of the running motion, speed or tracked (at most one runs).
    std::optional<ClientInfo> motion_owner() const;
    // Ends whichever motion runs; zero speed first if `send_zero`.
    void end_motion(EndReason reason, bool send_zero);

    // ---- braking at the soft limits (core_brake.cpp) ----
    SoftBrake soft_brake() const;
    // The age of the latest sample when it is younger than link.stale_ms.
    std::optional<Millis> fresh_attitude_age(SteadyTime now) const;
    // A speed command after braking; kLinkDown when an axis it moves needs
    // a fresh attitude and there is none.
    Outcome<Braked> brake_command(protocol::Axes speed) const;
    // A speed command whose every moving axis was braked: nothing moves.
    SpeedStarted stopped_at_limit(const ClientInfo& client, const Braked& braked);
    // On every attitude sample and keepalive tick: brakes the running speed
    // motion's axes near their limits, or ends it (kNoAttitude) when it
    // needs an attitude that is not fresh.
    void watch_motion();

    // ---- the read path and events (core.cpp) ----
    void on_bytes(std::span<const std::uint8_t> bytes);
    void on_frame(const protocol::FrameView& frame, SteadyTime now, WallTime wall);
    void on_attitude(const protocol::Attitude& attitude, SteadyTime now, WallTime wall);
    void on_link(const LinkEvent& event);
    void on_motion(const MotionEvent& event);
    void report_line_quality();
    void arm_quality_timer();

    boost::asio::io_context& io_;
    config::Config config_;
    std::shared_ptr<spdlog::logger> log_;
    SteadyTime started_;
    CoreObserver* observer_ = nullptr;
    std::vector<std::function<void(const LinkEvent&)>> link_listeners_;
    std::optional<AttitudeSample> latest_;
    Arbiter arbiter_;
    protocol::Decoder decoder_;
    SerialPort port_;
    LinkMonitor monitor_;
    Keepalive keepalive_;
    MotionTracker tracker_;  // angle and centre motions
    SettingsExchange settings_;
    boost::asio::steady_timer quality_timer_;
    boost::asio::steady_timer shutdown_timer_;
    protocol::DecoderStats reported_{};
    std::uint64_t seq_ = 0;
    std::uint64_t bad_messages_ = 0;
    bool stopping_ = false;
    RecordingState recording_ = RecordingState::kUnknown;  // assumed; unknown on each open
    SteadyTime speed_started_{};  // when the running speed motion started (status elapsed_ms)
};

}  // namespace gport::daemon
