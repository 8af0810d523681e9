// gport::daemon::Core — the one object that owns the gimbal link and keeps it
// safe for every client: serial link with reconnect, link health, the speed
// keepalive and deadman, settings requests, control arbitration, counters.
#pragma once

#include <spdlog/logger.h>

#include <boost/asio/io_context.hpp>
#include <functional>
#include <memory>

#include "gport/config/config.hpp"
#include "gport/daemon/api.hpp"

namespace gport::daemon {

class Core final : public Api {
  public:
    Core(boost::asio::io_context& io, const config::Config& config,
         std::shared_ptr<spdlog::logger> log);
    ~Core() override;
    Core(const Core&) = delete;
    Core& operator=(const Core&) = delete;

    // Opens the device (retrying forever in the background) and starts timers.
    void start();
    // Stops any running motion with a zero-speed frame, waits (bounded) for it
    // to reach the device, closes the device, then calls done.
    void shutdown(std::function<void()> done);
    // SIGHUP: applies the keys that may change at run time — who may command
    // (a fresh access policy, so no cached decision survives) and the default
    // and longest speed durations. A running motion is left as it is.
    void reload(const config::Config& config);
    // Also told of every link change (e.g. for the service manager's status).
    void add_link_listener(std::function<void(const LinkEvent&)> listener);

    void set_observer(CoreObserver* observer) override;
    Status status() const override;
    std::optional<AttitudeSample> latest_attitude() const override;
    bool may_command(const ClientInfo& client) const override;
    Outcome<SpeedStarted> speed(const ClientInfo& client, protocol::Axes speed,
                                std::optional<Millis> duration) override;
    Outcome<Done> stop(const ClientInfo& client) override;
    Outcome<Done> angle(const ClientInfo& client, protocol::Axes angle) override;
    Outcome<Done> center(const ClientInfo& client) override;
    Outcome<Done> lock(const ClientInfo& client) override;
    Outcome<Done> photo(const ClientInfo& client) override;
    Outcome<Done> record(const ClientInfo& client) override;
    Outcome<std::optional<ClientInfo>> acquire(const ClientInfo& client) override;
    Outcome<std::optional<ClientInfo>> release(const ClientInfo& client) override;
    void get_settings(const ClientInfo& client, SettingsCallback done) override;
    void set_settings(const ClientInfo& client, SettingsChange change,
                      SettingsCallback done) override;
    void client_gone(const ClientInfo& client) override;
    void client_closed(const ClientInfo& client) override;

  private:
    class Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace gport::daemon
