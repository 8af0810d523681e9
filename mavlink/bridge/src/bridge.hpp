// gport-mavlink's event loop: gportd's client on one side (AsyncClient,
// reconnecting with backoff), the MAVLink transport on the other, and the
// timers of the heartbeat and the attitude status (docs/mavlink.md).
//
// Every MAVLink frame passes, in this order, before it is acted on: the
// signature rules (with a key; without one, signed frames are dropped: they
// cannot be checked), the trust rules (trust.hpp: who may command, who is
// the vehicle), and the addressing (our system and component, or
// broadcast). A frame that passed the first two (it may still be addressed
// to another component) makes its UDP sender the reply peer. What is
// refused is counted and logged within bounds.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "camera_component.hpp"
#include "gport/base/token_bucket.hpp"
#include "gport/client/async_client.hpp"
#include "gport/mavlink/bridge/log_limit.hpp"
#include "gport/mavlink/bridge/mapping.hpp"
#include "gport/mavlink/bridge/options.hpp"
#include "gport/mavlink/bridge/rate_lease.hpp"
#include "gport/mavlink/bridge/stream_requests.hpp"
#include "gport/mavlink/bridge/trust.hpp"
#include "gport/mavlink/bridge/vehicle_yaw.hpp"
#include "gport/mavlink/decoder.hpp"
#include "gport/mavlink/messages.hpp"
#include "logbook.hpp"
#include "signing_session.hpp"
#include "transport.hpp"
#include "vehicle_publisher.hpp"

namespace gport::mavlink::bridge {

// Transport, trust and routing; the gimbal component (154) itself; the
// camera component (camera_component.hpp) as a part it routes to.
class Bridge : private CameraHost {
  public:
    // Reply-peer changes named a minute; the rest are counted (Logbook),
    // with no lifetime cap. (Untrusted senders: one named a minute, the
    // rest counted: a sender repeats itself, a peer change does not.)
    static constexpr std::uint32_t kPeerLinesPerMinute = 10;
    // The motion connection's share of gportd's request budget (its
    // socket.max_requests_per_s, 200 by default, must stay above), its
    // burst and what of it only a stop (a zero rate) may spend; how long the
    // vehicle's last GIMBAL_DEVICE_SET_ATTITUDE overrules a ground station's.
    static constexpr double kMotionPerSecond = 100;
    static constexpr double kMotionBurst = 20;
    static constexpr double kStopReserve = 5;
    static constexpr auto kManagerPrecedence = std::chrono::seconds(5);  // the longest lease

    // `signing`: the session of --signing-key, or null without a key.
    Bridge(boost::asio::io_context& io, Options options, std::unique_ptr<SigningSession> signing,
           Logbook& log);
    // Opens the transport (throws std::runtime_error when it cannot) and
    // starts connecting to gportd and the timers.
    void start();
    // At exit: the pending warning summaries, the counters, the signing
    // timestamp.
    void finish();

  private:
    using Clock = std::chrono::steady_clock;

    // gportd (bridge.cpp)
    void connect();
    void retry_connect(const client::Error& error);
    void on_connected();
    void on_disconnected(const std::string& why);
    void on_notification(const client::Notification& notification);
    void dispatch(Command command);
    void send_pending();
    void send_motion(const Command& command);
    bool lease_refused(const client::Error& error);
    void motion_done(const std::optional<client::Error>& error, const char* what);

    // MAVLink in (bridge_mavlink.cpp)
    void on_bytes(std::span<const std::uint8_t> bytes, bool fresh_source);
    void on_frame(const FrameView& frame);
    bool admitted(const FrameView& frame, const Message& message);
    void refuse(const FrameView& frame, TrustVerdict verdict);
    void log_peer(const FrameView& frame, const std::string& peer);
    void handle(const Header& from, const Message& message);
    void on_heartbeat(const Header& header, const Heartbeat& heartbeat);
    void on_command(const Requester& from, const CommandLong& command);
    void on_set_attitude(const Header& from, const GimbalDeviceSetAttitude& message);
    void on_autopilot_state(const AutopilotStateForGimbalDevice& message);
    void request_message(const Requester& from, const CommandLong& command);
    void on_attitude(const Header& from, const Attitude& message);
    std::optional<double> vehicle_yaw_deg() override;  // fresh, or none; logs a change of source
    void on_position(const Header& from, const GlobalPositionInt& message);
    void on_gps(const Header& from, const GpsRawInt& message);
    void on_system_time(const Header& from, const SystemTime& message);
    // The autopilot's streams we need, asked for when they do not come
    // (stream_requests.hpp; bridge_streams.cpp), and its answers.
    void request_streams();
    void on_ack(const Header& from, const CommandAck& message);

    // CameraHost: what the camera component asks of the bridge.
    void send_from(std::uint8_t compid, const Message& message, const Origin& to) override {
        send(message, to, compid);
    }
    void ack_from(std::uint8_t compid, const Requester& to, std::uint16_t command,
                  std::uint8_t result) override {
        ack(to, command, result, compid);
    }
    client::AsyncClient& gportd() override { return gportd_; }
    bool gportd_connected() const override { return connected_; }
    std::uint8_t vehicle_sysid() const override { return trust_.vehicle().value_or(0); }
    const std::optional<client::AttitudeSample>& newest_sample() const override { return sample_; }
    std::uint32_t position_requests() const override {
        return streams_.attempts(GlobalPositionInt::kId);
    }

    // MAVLink out: to the peer, or (replies) to a requester's origin; from
    // the gimbal's component (compid 0) or the given one.
    void ack(const Requester& to, std::uint16_t command, std::uint8_t result,
             std::uint8_t compid = 0);
    void send(const Message& message, const Origin& to = std::nullopt, std::uint8_t compid = 0);

    // timers (bridge.cpp)
    void send_heartbeat(const Origin& to = std::nullopt);
    void heartbeat_tick();
    void attitude_tick();
    Health health() const override;
    std::uint32_t time_boot_ms() const override;

    boost::asio::io_context& io_;
    Options options_;
    std::unique_ptr<SigningSession> signing_;
    Logbook& log_;
    std::unique_ptr<Transport> transport_;
    client::AsyncClient gportd_;  // subscription, limits, the camera
    client::AsyncClient motion_;  // angle, speed, centre only (bridge_motion.cpp)
    Decoder decoder_;
    Trust trust_;
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
    VehicleYaw vehicle_yaw_;
    YawSource yaw_source_ = YawSource::kNone;  // the one last logged
    RateLease rate_lease_;
    std::optional<Clock::time_point> manager_seen_;
    std::uint16_t mode_flags_ = gimbal_flags_default();
    bool idle_logged_ = false;  // the all-NaN stream said once, until a target comes

    StreamRequests streams_;
    CameraComponent camera_;
    VehiclePublisher vehicle_;
    std::uint8_t seq_ = 0;         // the gimbal's frames
    std::uint8_t camera_seq_ = 0;  // the camera's: a sequence per component

    // One motion request to gportd at a time (a stop may go beside it); the
    // newest waiting one replaces an older one (a 50 Hz stream never queues
    // up); within the motion budget (bridge_motion.cpp).
    std::size_t motion_in_flight_ = 0;
    std::uint64_t motion_sent_ = 0;
    std::optional<Command> motion_pending_;
    base::TokenBucket motion_budget_{kMotionPerSecond, kMotionBurst};
    boost::asio::steady_timer motion_timer_;
    bool motion_timer_armed_ = false;
    std::uint64_t motion_timer_generation_ = 0;
    // The vehicle's last GIMBAL_DEVICE_SET_ATTITUDE: a ground station's are
    // overruled within kManagerPrecedence of it.
    std::optional<Clock::time_point> manager_commands_at_;

    // What was refused, for the log at exit.
    struct Counters {
        std::uint64_t accepted = 0;        // frames acted on (or addressed elsewhere)
        std::uint64_t undecodable = 0;     // valid frames whose payload did not decode
        std::uint64_t signed_no_key = 0;   // signed frames while we have no key
        std::uint64_t untrusted = 0;       // refused by the trust rules
        std::uint64_t gcs_heartbeats = 0;  // a ground station's: normal, not used
        std::uint64_t bad_positions = 0;   // not the autopilot's, or out of bounds (position.hpp)
        std::uint64_t overruled = 0;       // a ground station's motion while the manager commands
    } counters_;

    static std::uint16_t gimbal_flags_default();
};

}  // namespace gport::mavlink::bridge
