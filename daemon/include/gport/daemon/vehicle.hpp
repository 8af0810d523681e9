// The vehicle's state as a trusted source (gport-mavlink, from the
// autopilot) publishes it, and what gportd makes of it: the vehicle at the
// instant of a capture (docs/api.md, "The vehicle"). No JSON here.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "gport/daemon/events.hpp"

namespace gport::daemon {

// One position sample, at the autopilot's boot time `boot_ms` (MAVLink's
// time_boot_ms: GLOBAL_POSITION_INT's, with GPS_RAW_INT's fix and accuracy).
struct VehiclePosition {
    std::uint32_t boot_ms = 0;
    double lat_deg = 0;  // WGS84
    double lon_deg = 0;
    double alt_msl_m = 0;
    std::optional<double> alt_rel_m;              // above home
    std::array<double, 3> velocity_ned{0, 0, 0};  // m/s: north, east, down
    std::optional<double> heading_deg;            // 0 to 360, true north
    std::optional<double> yaw_rate_dps;           // clockwise seen from above
    std::optional<int> fix;                       // MAVLink GPS_FIX_TYPE, 0 to 8
    std::optional<double> h_acc_m;                // 1-sigma, as the receiver reports
    std::optional<double> v_acc_m;
    std::optional<int> satellites;
};

// The autopilot's UTC at its boot time `boot_ms` (SYSTEM_TIME).
struct VehicleTime {
    std::uint32_t boot_ms = 0;
    std::int64_t utc_us = 0;
};

// What one publish_vehicle carries: either part or both.
struct VehicleReport {
    std::optional<VehiclePosition> position;
    std::optional<VehicleTime> time;
};

// The vehicle at an instant: the newest position carried forward to it
// with its velocity (and yaw rate), its accuracy grown by the carry, and the
// autopilot's UTC at that instant. Untagged (why says why) when there is no
// position fit to stamp with; the UTC may be known either way.
struct VehicleStamp {
    bool tagged = false;
    std::string why;  // untagged: the reason, for people
    double lat_deg = 0;
    double lon_deg = 0;
    double alt_msl_m = 0;
    std::optional<double> alt_rel_m;
    std::array<double, 3> velocity_ned{0, 0, 0};
    std::optional<double> heading_deg;
    std::optional<double> h_acc_m;  // the sample's, plus age × horizontal speed
    std::optional<double> v_acc_m;  // the sample's, plus age × vertical speed
    std::optional<int> fix;
    std::optional<int> satellites;
    Millis age{0};                       // from the sample to the instant
    std::optional<std::int64_t> utc_us;  // the autopilot's UTC at the instant
};

// status's "vehicle" (nullopt there: nothing was ever published).
struct VehicleStatus {
    std::optional<ClientInfo> source;  // the connection publishing, while it is open
    std::optional<VehiclePosition> position;
    std::optional<Millis> position_age;  // of the newest sample, now
    bool utc_known = false;
    std::optional<Millis> time_age;  // of the newest SYSTEM_TIME, now
    std::uint64_t published = 0;     // reports taken
    std::uint64_t refused = 0;       // reports refused (access, values, another source)
    std::uint64_t resets = 0;        // the autopilot rebooted (its boot time went back)
};

}  // namespace gport::daemon
