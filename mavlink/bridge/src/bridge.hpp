// gport-mavlink's event loop: gportd's client on one side (AsyncClient,
// reconnecting with backoff), the MAVLink transport on the other, and the
// timers of the heartbeat and the attitude status (docs/mavlink.md).
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "gport/client/async_client.hpp"
#include "gport/mavlink/bridge/mapping.hpp"
#include "gport/mavlink/bridge/options.hpp"
#include "gport/mavlink/decoder.hpp"
#include "gport/mavlink/messages.hpp"
#include "transport.hpp"

namespace gport::mavlink::bridge {

class Bridge {
  public:
    Bridge(boost::asio::io_context& io, Options options);
    // Opens the transport (throws std::runtime_error when it cannot) and
    // starts connecting to gportd and the timers.
    void start();

  private:
    using Clock = std::chrono::steady_clock;

    // gportd
    void connect();
    void on_connected();
    void on_disconnected(const std::string& why);
    void on_notification(const client::Notification& notification);
    void dispatch(Command command);
    void send_motion(const Command& command);
    void motion_done(const std::optional<client::Error>& error, const char* what);

    // MAVLink
    void on_bytes(std::span<const std::uint8_t> bytes);
    void on_frame(const FrameView& frame);
    void on_heartbeat(const Header& header, const Heartbeat& heartbeat);
    void on_command(const Header& header, const CommandLong& command);
    void on_set_attitude(const GimbalDeviceSetAttitude& message);
    void on_autopilot_state(const AutopilotStateForGimbalDevice& message);
    void request_message(const Header& from, const CommandLong& command);
    void camera(const Header& from, const CommandLong& command);
    void record(const Header& from, std::uint16_t command, bool on, bool force);
    void ack(const Header& to, std::uint16_t command, std::uint8_t result);
    void send(const Message& message);

    // timers
    void send_heartbeat();
    void heartbeat_tick();
    void attitude_tick();
    Health health() const;
    std::uint32_t time_boot_ms() const;
    void warn_once(std::string& last, const std::string& text);

    boost::asio::io_context& io_;
    Options options_;
    std::unique_ptr<Transport> transport_;
    client::AsyncClient gportd_;
    Decoder decoder_;
    SystemId sysid_;
    AngleFilter filter_;
    boost::asio::steady_timer reconnect_timer_;
    boost::asio::steady_timer heartbeat_timer_;
    boost::asio::steady_timer attitude_timer_;
    std::chrono::milliseconds backoff_{100};
    Clock::time_point started_ = Clock::now();

    bool connected_ = false;
    std::string link_state_;
    std::optional<client::AttitudeSample> sample_;
    std::optional<client::Limits> limits_;
    std::optional<double> vehicle_yaw_deg_;
    std::optional<double> vehicle_yaw_rate_dps_;
    std::optional<Clock::time_point> manager_seen_;
    std::uint16_t mode_flags_ = gimbal_flags_default();
    std::uint8_t seq_ = 0;

    // One motion request to gportd at a time; the newest waiting one replaces
    // an older one (a 50 Hz stream never queues up).
    bool motion_in_flight_ = false;
    std::optional<Command> motion_pending_;

    std::uint64_t ignored_messages_ = 0;
    std::string last_motion_error_;
    std::string last_mapping_error_;
    std::string last_connect_error_;

    static std::uint16_t gimbal_flags_default();
};

}  // namespace gport::mavlink::bridge
