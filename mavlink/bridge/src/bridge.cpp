#include "bridge.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>

#include "gport/mavlink/attitude.hpp"
#include "gport/mavlink/enums.hpp"

namespace gport::mavlink::bridge {

namespace asio = boost::asio;
using namespace std::chrono_literals;

namespace {

constexpr auto kBackoffMax = 5000ms;
constexpr auto kManagerTimeout = 3s;

TrustPolicy policy_of(const Options& o) {
    TrustPolicy policy;
    policy.vehicle = o.sysid;
    for (auto id : o.gcs_sysids) {
        policy.ground_stations.set(id);
    }
    policy.own_components.set(o.compid);
    if (o.camera) {
        policy.own_components.set(kCameraCompid);
    }
    return policy;
}

// ATTITUDE (10 Hz) for the vehicle's yaw; GLOBAL_POSITION_INT (5 Hz),
// GPS_RAW_INT (2 Hz) and SYSTEM_TIME (1 Hz) for the vehicle's state that
// gportd stamps every capture with (vehicle_publisher.hpp), whoever asks for
// the photo: wanted with or without the camera component.
std::vector<StreamRequests::Stream> wanted_streams() {
    return {{Attitude::kId, 100000},
            {GlobalPositionInt::kId, 200000},
            {GpsRawInt::kId, 500000},
            {SystemTime::kId, 1000000}};
}

}  // namespace

std::uint16_t Bridge::gimbal_flags_default() {
    return gimbal_flags::kRollLock | gimbal_flags::kPitchLock;
}

Bridge::Bridge(asio::io_context& io, Options options, std::unique_ptr<SigningSession> signing,
               Logbook& log)
    : io_(io),
      options_(std::move(options)),
      signing_(std::move(signing)),
      log_(log),
      gportd_(io),
      motion_(io),
      trust_(policy_of(options_)),
      reconnect_timer_(io),
      heartbeat_timer_(io),
      attitude_timer_(io),
      rate_lease_(std::chrono::milliseconds(options_.lease_ms)),
      streams_(wanted_streams()),
      camera_(io, options_, log_, *this),
      vehicle_(log_),
      motion_timer_(io) {}

void Bridge::start() {
    transport_ = open_transport(io_, options_.mavlink);
    transport_->start([this](std::span<const std::uint8_t> bytes, bool fresh_source) {
        on_bytes(bytes, fresh_source);
    });
    gportd_.on_notification([this](const client::Notification& n) { on_notification(n); });
    gportd_.on_disconnect([this](const client::Error& e) { on_disconnected(e.message()); });
    motion_.on_disconnect([this](const client::Error& e) { on_disconnected(e.message()); });
    spdlog::info(
        "gport-mavlink: MAVLink on {}, gportd at {}, compid {}{}; vehicle system {}, ground "
        "stations {}; signing {}",
        to_string(options_.mavlink), options_.socket, options_.compid,
        options_.camera ? fmt::format(" (camera: compid {})", kCameraCompid) : std::string(),
        options_.sysid ? std::to_string(*options_.sysid)
                       : "auto (adopted from the first autopilot heartbeat: spoofable)",
        to_string(options_.gcs_sysids), signing_ ? "on" : "off");
    if (camera_.enabled()) {
        camera_.load_image_count();
    }
    connect();
    heartbeat_tick();
    attitude_tick();
}

void Bridge::finish() {
    log_.flush();
    const auto& d = decoder_.stats();
    std::string signing = "off";
    if (signing_) {
        const auto& counts = signing_->counts();
        signing.clear();
        for (const SignatureCheck check : kSignatureChecks) {
            signing += fmt::format("{}{} {}", signing.empty() ? "" : ", ",
                                   counts[static_cast<std::size_t>(check)], to_string(check));
        }
        signing_->close();
    }
    spdlog::info(
        "mavlink: {} frames taken, {} refused by the trust rules, {} ground-station heartbeats "
        "(not used), {} signed without a key, {} undecodable, {} positions dropped; decoder: {} "
        "bad CRC, {} bad length, {} unknown flags, {} MAVLink 1, {} of messages not decoded here "
        "(not errors); signing: {}; {} frames unsent (no peer yet), {} send failures; {} "
        "ground-station GIMBAL_DEVICE_SET_ATTITUDE overruled by the vehicle's; vehicle state: {} "
        "reports taken by gportd, {} refused",
        counters_.accepted, counters_.untrusted, counters_.gcs_heartbeats, counters_.signed_no_key,
        counters_.undecodable, counters_.bad_positions, d.crc_errors, d.length_errors,
        d.header_errors, d.v1_frames, d.unknown_ids, signing, transport_ ? transport_->unsent() : 0,
        transport_ ? transport_->send_failures() : 0, counters_.overruled,
        vehicle_.counters().published, vehicle_.counters().refused);
}

// ---- gportd ---------------------------------------------------------------------

// Both connections, the motion one second; either failing, both again.
void Bridge::connect() {
    gportd_.async_connect(options_.socket, [this](std::optional<client::Error> error) {
        if (!error) {
            motion_.async_connect(options_.socket, [this](std::optional<client::Error> failed) {
                if (!failed) {
                    on_connected();
                    return;
                }
                gportd_.close();
                retry_connect(*failed);
            });
            return;
        }
        retry_connect(*error);
    });
}

void Bridge::retry_connect(const client::Error& error) {
    // The library's message names the socket already ("cannot connect
    // to PATH: ..."); others get it added.
    const auto& why = error.message();
    log_.warn("gportd: cannot connect",
              "gportd: " +
                  (why.find(options_.socket) != std::string::npos
                       ? why
                       : "cannot connect to " + options_.socket + ": " + why) +
                  "; retrying with backoff");
    reconnect_timer_.expires_after(backoff_);
    reconnect_timer_.async_wait([this](boost::system::error_code ec) {
        if (!ec) {
            connect();
        }
    });
    backoff_ = std::min<std::chrono::milliseconds>(backoff_ * 2, kBackoffMax);
}

void Bridge::on_connected() {
    backoff_ = 100ms;
    connected_ = true;
    filter_.reset();
    spdlog::info("gportd: connected to {}", options_.socket);
    vehicle_.connected(gportd_);
    gportd_.async_status([this](std::optional<client::Error> error, client::Status status) {
        if (!error) {
            link_state_ = status.link.state;
        }
    });
    gportd_.async_limits([this](std::optional<client::Error> error, client::Limits limits) {
        if (error) {
            log_.warn("gportd: limits unknown",
                      "gportd: limits unknown (" + error->message() +
                          "); GIMBAL_DEVICE_INFORMATION gives the G-Port's mechanical range");
            return;
        }
        limits_ = limits;
    });
    gportd_.async_subscribe({"attitude", "link"}, std::max(options_.attitude_rate_hz * 2, 1.0),
                            [this](std::optional<client::Error> error, client::Subscription) {
                                if (error) {
                                    log_.warn("gportd: subscribe refused",
                                              "gportd: subscribe refused: " + error->message());
                                }
                            });
}

void Bridge::on_disconnected(const std::string& why) {
    if (!connected_) {
        return;
    }
    connected_ = false;
    vehicle_.disconnected();
    gportd_.close();  // either broke: both start again together
    motion_.close();
    link_state_.clear();
    sample_.reset();
    log_.warn("gportd: connection lost", "gportd: connection lost (" + why + "); reconnecting");
    backoff_ = 100ms;
    connect();
}

void Bridge::on_notification(const client::Notification& notification) {
    if (const auto* sample = std::get_if<client::AttitudeSample>(&notification)) {
        sample_ = *sample;
    } else if (const auto* link = std::get_if<client::LinkEvent>(&notification)) {
        if (link->state != link_state_) {
            spdlog::info("gportd: link {} ({})", link->state, link->reason);
        }
        link_state_ = link->state;
    }
}

// ---- timers ----------------------------------------------------------------------

Health Bridge::health() const {
    Health h;
    h.gportd_connected = connected_;
    h.link_state = link_state_;
    h.manager_seen = manager_seen_ && Clock::now() - *manager_seen_ < kManagerTimeout;
    return h;
}

std::uint32_t Bridge::time_boot_ms() const {
    return static_cast<std::uint32_t>(
        std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - started_).count());
}

void Bridge::send_heartbeat(const Origin& to) {
    Heartbeat hb;
    hb.type = mav_type::kGimbal;
    hb.autopilot = mav_autopilot::kInvalid;
    hb.system_status = system_status(health());
    send(hb, to);
}

void Bridge::heartbeat_tick() {
    send_heartbeat();
    camera_.send_heartbeat();  // when announced
    request_streams();
    log_.tick();
    heartbeat_timer_.expires_after(1s);
    heartbeat_timer_.async_wait([this](boost::system::error_code ec) {
        if (!ec) {
            heartbeat_tick();
        }
    });
}

void Bridge::attitude_tick() {
    AttitudeInputs in;
    in.sample = sample_;
    in.vehicle_yaw_deg = vehicle_yaw_deg();
    if (const auto reading = vehicle_yaw_.at(Clock::now())) {
        in.vehicle_yaw_rate_dps = reading->rate_dps;
    }
    in.mode_flags = mode_flags_;
    in.time_boot_ms = time_boot_ms();
    send(make_attitude_status(in, health(), options_.invert));
    const auto period = std::chrono::duration_cast<Clock::duration>(
        std::chrono::duration<double>(1.0 / options_.attitude_rate_hz));
    // Scheduled from the previous expiry, not from now: the rate does not drift.
    const auto now = Clock::now();
    const auto next = attitude_timer_.expiry() + period;
    attitude_timer_.expires_at(next > now ? next : now + period);
    attitude_timer_.async_wait([this](boost::system::error_code ec) {
        if (!ec) {
            attitude_tick();
        }
    });
}

}  // namespace gport::mavlink::bridge
