// Core's private state and the logic that ties its parts together.
#pragma once

#include <spdlog/logger.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "access_policy.hpp"
#include "gport/daemon/core.hpp"
#include "gport/protocol/decoder.hpp"
#include "keepalive.hpp"
#include "link_monitor.hpp"
#include "serial_port.hpp"
#include "settings_exchange.hpp"

namespace gport::daemon {

class Core::Impl {
  public:
    Impl(boost::asio::io_context& io, const config::Config& config,
         std::shared_ptr<spdlog::logger> log);

    void start();
    void shutdown(std::function<void()> done);
    Status status() const;

    Outcome<SpeedStarted> speed(const ClientInfo& client, protocol::Axes speed,
                                std::optional<Millis> duration);
    Outcome<Done> stop(const ClientInfo& client);
    Outcome<Done> position(const ClientInfo& client, const protocol::Control& control,
                           MotionMode mode);
    Outcome<Done> camera(const ClientInfo& client, protocol::CameraAction action);
    Outcome<std::optional<ClientInfo>> acquire(const ClientInfo& client);
    Outcome<std::optional<ClientInfo>> release(const ClientInfo& client);
    void settings(const ClientInfo& client, std::optional<SettingsChange> change,
                  SettingsCallback done);
    void client_gone(const ClientInfo& client);
    void client_closed(const ClientInfo& client);
    void reload(const config::Config& config);  // defined in core.cpp

    CoreObserver* observer = nullptr;
    std::vector<std::function<void(const LinkEvent&)>> link_listeners;
    std::optional<AttitudeSample> latest;
    AccessPolicy access;

  private:
    std::optional<CommandError> check_access(const ClientInfo& client) const;
    std::optional<CommandError> check_command(const ClientInfo& client) const;
    std::optional<CommandError> held_by_other(const ClientInfo& client) const;
    CommandError link_down() const;
    bool send(const protocol::Frame& frame);
    bool send_control(const protocol::Control& control);
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
    protocol::Decoder decoder_;
    SerialPort port_;
    LinkMonitor monitor_;
    Keepalive keepalive_;
    SettingsExchange settings_;
    std::optional<ClientInfo> controller_;
    boost::asio::steady_timer quality_timer_;
    boost::asio::steady_timer shutdown_timer_;
    protocol::DecoderStats reported_{};
    std::uint64_t seq_ = 0;
    std::uint64_t bad_messages_ = 0;
    bool stopping_ = false;
};

}  // namespace gport::daemon
