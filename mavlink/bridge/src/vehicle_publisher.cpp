#include "vehicle_publisher.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <limits>
#include <utility>

namespace gport::mavlink::bridge {
namespace {

constexpr std::uint16_t kUnknownHeading = std::numeric_limits<std::uint16_t>::max();
constexpr std::uint8_t kUnknownSatellites = 255;

// A boot time after `last` (none yet: any); a repeated or older one is not sent.
bool newer(std::uint32_t boot_ms, std::optional<std::uint32_t>& last) {
    if (last && boot_ms <= *last && *last - boot_ms <= 1000) {
        return false;
    }
    last = boot_ms;
    return true;
}

}  // namespace

void VehiclePublisher::on_position(const GlobalPositionInt& p, std::optional<double> yaw_rate_dps,
                                   Clock::time_point now) {
    if (!newer(p.time_boot_ms, last_position_ms_)) {
        return;
    }
    client::VehiclePosition out;
    out.boot_ms = p.time_boot_ms;
    out.lat = p.lat / 1e7;
    out.lon = p.lon / 1e7;
    out.alt_msl_m = p.alt / 1e3;
    out.alt_rel_m = p.relative_alt / 1e3;
    out.velocity_ned = {p.vx / 100.0, p.vy / 100.0, p.vz / 100.0};  // cm/s
    if (p.hdg != kUnknownHeading) {
        out.heading_deg = p.hdg / 100.0;
    }
    out.yaw_rate_dps = yaw_rate_dps;
    if (gps_ && now - gps_->second <= kGpsMaxAge) {
        const auto& g = gps_->first;
        out.fix = g.fix_type <= 8 ? std::optional<int>(g.fix_type) : std::nullopt;
        if (g.satellites_visible != kUnknownSatellites) {
            out.satellites = g.satellites_visible;
        }
        if (g.h_acc > 0) {  // mm; 0: the autopilot does not know it (or an old one)
            out.h_acc_m = g.h_acc / 1e3;
        }
        if (g.v_acc > 0) {
            out.v_acc_m = g.v_acc / 1e3;
        }
    }
    waiting_.position = out;
    send();
}

void VehiclePublisher::on_gps(const GpsRawInt& gps, Clock::time_point now) {
    gps_.emplace(gps, now);
}

void VehiclePublisher::on_system_time(const SystemTime& time) {
    if (time.time_unix_usec == 0) {
        if (!no_utc_logged_) {
            spdlog::info(
                "mavlink: the autopilot's SYSTEM_TIME has no UTC yet (no GPS time); captures "
                "carry the companion's clock only until it has");
            no_utc_logged_ = true;
        }
        return;
    }
    if (!newer(time.time_boot_ms, last_time_ms_)) {
        return;
    }
    waiting_.time =
        client::VehicleTime{time.time_boot_ms, static_cast<std::int64_t>(time.time_unix_usec)};
    send();
}

void VehiclePublisher::connected(client::AsyncClient& gportd) {
    gportd_ = &gportd;
    in_flight_ = false;
    send();
}

void VehiclePublisher::disconnected() {
    gportd_ = nullptr;
    in_flight_ = false;
}

void VehiclePublisher::send() {
    if (gportd_ == nullptr || in_flight_ || (!waiting_.position && !waiting_.time)) {
        return;
    }
    in_flight_ = true;
    auto* connection = gportd_;
    connection->async_publish_vehicle(
        std::exchange(waiting_, {}),
        [this, connection](std::optional<client::Error> error, client::Done) {
            if (connection != gportd_) {
                return;  // a connection since closed
            }
            done(error);
        });
}

void VehiclePublisher::done(const std::optional<client::Error>& error) {
    in_flight_ = false;
    if (!error) {
        ++counters_.published;
    } else {
        ++counters_.refused;
        if (error->is(client::ErrorCode::kPermission)) {
            log_.warn("gportd: vehicle state refused", [&] {
                return fmt::format(
                    "gportd: it does not take the vehicle's state from this user ({}); captures "
                    "are not stamped with the vehicle's position until gportd's "
                    "access.vehicle_uids lists it (further refusals are counted)",
                    error->message());
            });
        } else {
            log_.warn("gportd: vehicle state refused (other)", [&] {
                return fmt::format("gportd: refused the vehicle's state: {}", error->message());
            });
        }
    }
    send();
}

}  // namespace gport::mavlink::bridge
