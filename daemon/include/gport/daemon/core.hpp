// gport::daemon::Core — the one object that owns the gimbal device and keeps
// it safe for every client: the gimbal's link (GimbalLink: the serial port,
// the read path, link health), settings requests, control arbitration, the
// camera, status and counters; the motion
// policy (keepalive, tracking, limits, braking, failsafe) is its Motion part
// (core/motion.hpp), to which it hands admitted commands. Clients see it only
// as a daemon::Api; the program that runs gportd constructs it, and so sees
// its parts (gport/daemon/core/).
#pragma once

#include <spdlog/logger.h>

#include <boost/asio/io_context.hpp>
#include <functional>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "gport/config/config.hpp"
#include "gport/daemon/api.hpp"
#include "gport/daemon/core/arbiter.hpp"
#include "gport/daemon/core/camera_gate.hpp"
#include "gport/daemon/core/gimbal_link.hpp"
#include "gport/daemon/core/motion.hpp"
#include "gport/daemon/core/settings_exchange.hpp"
#include "gport/daemon/core/vehicle_track.hpp"

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
    void set_observer(CoreObserver* observer) override {
        observer_ = observer;
        motion_.set_observer(observer);
    }
    Status status() const override;
    std::optional<AttitudeSample> latest_attitude() const override { return latest_; }
    bool may_command(const ClientInfo& client) const override {
        return arbiter_.may_command(client);
    }
    config::LimitsConfig limits() const override { return motion_.limits(); }
    Millis max_duration() const override { return motion_.max_duration(); }
    Outcome<SpeedStarted> speed(const ClientInfo& client, protocol::Axes speed,
                                std::optional<Millis> duration, bool clamp = false,
                                std::optional<Millis> lease = std::nullopt) override;
    Outcome<Done> stop(const ClientInfo& client) override;
    Outcome<AngleSent> angle(const ClientInfo& client, protocol::Axes angle, bool clamp = false,
                             MotionEndCallback on_end = {}) override;
    Outcome<AngleSent> center(const ClientInfo& client, MotionEndCallback on_end = {}) override;
    Outcome<Done> lock(const ClientInfo& client) override;
    Outcome<CaptureMoment> photo(const ClientInfo& client) override;
    Outcome<Done> publish_vehicle(const ClientInfo& client, const VehicleReport& report) override;
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
    // admit(client, kAccessAndControl), then the command.
    template <class Command>
    auto admitted(const ClientInfo& client, Command&& command) -> decltype(command()) {
        if (auto refused = admit(client, Arbiter::Needs::kAccessAndControl)) {
            return std::move(*refused);
        }
        return command();
    }

    // The moment of the camera frame just queued (core_commands.cpp).
    CaptureMoment capture_moment();

    // ---- events (core.cpp) ----
    void on_attitude(const protocol::Attitude& attitude, SteadyTime now, WallTime wall);
    void on_link(const LinkEvent& event);

    config::Config config_;  // as started: read only for keys a reload never changes
    std::shared_ptr<spdlog::logger> log_;
    SteadyTime started_;
    CoreObserver* observer_ = nullptr;
    std::vector<std::function<void(const LinkEvent&)>> link_listeners_;
    std::optional<AttitudeSample> latest_;  // the newest sample: Motion and its tracker read it
    Arbiter arbiter_;
    GimbalLink link_;
    Motion motion_;  // after link_: it sends through it
    SettingsExchange settings_;
    std::uint64_t seq_ = 0;
    CameraGate camera_;
    VehicleTrack vehicle_;
};

}  // namespace gport::daemon
