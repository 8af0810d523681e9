// What gport-mavlink hears from the vehicle's autopilot, published to gportd
// (publish_vehicle; docs/mavlink.md, "The vehicle's state for gportd"), which
// stamps every capture with it, whichever client asked for the photo: each
// GLOBAL_POSITION_INT with the newest GPS_RAW_INT's fix and accuracy and
// ATTITUDE's yaw rate, and each SYSTEM_TIME that carries a UTC.
//
// One report to gportd at a time; what arrives meanwhile waits, the newest
// position and time replacing older ones (5 Hz and 1 Hz: nothing queues
// up). Boot times that do not increase are not sent (gportd refuses them).
// gportd's refusals are counted and logged within bounds (Logbook): a
// gportd that does not trust this user says so once, with what to change.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>

#include "gport/client/async_client.hpp"
#include "gport/mavlink/messages.hpp"
#include "logbook.hpp"

namespace gport::mavlink::bridge {

class VehiclePublisher {
  public:
    using Clock = std::chrono::steady_clock;
    // A GPS_RAW_INT older than this is not joined to a position.
    static constexpr auto kGpsMaxAge = std::chrono::seconds(2);

    explicit VehiclePublisher(Logbook& log) : log_(log) {}

    // The autopilot's messages, already checked (trusted, from its
    // autopilot component, position in range).
    void on_position(const GlobalPositionInt& position, std::optional<double> yaw_rate_dps,
                     Clock::time_point now);
    void on_gps(const GpsRawInt& gps, Clock::time_point now);
    void on_system_time(const SystemTime& time);

    // gportd's connection: sends what waits once connected.
    void connected(client::AsyncClient& gportd);
    void disconnected();

    struct Counters {
        std::uint64_t published = 0;  // reports gportd took
        std::uint64_t refused = 0;    // reports gportd refused
    };
    const Counters& counters() const { return counters_; }

  private:
    void send();
    void done(const std::optional<client::Error>& error);

    Logbook& log_;
    client::AsyncClient* gportd_ = nullptr;
    bool in_flight_ = false;
    client::VehicleReport waiting_;
    std::optional<std::pair<GpsRawInt, Clock::time_point>> gps_;
    std::optional<std::uint32_t> last_position_ms_;
    std::optional<std::uint32_t> last_time_ms_;
    bool no_utc_logged_ = false;
    Counters counters_;
};

}  // namespace gport::mavlink::bridge
