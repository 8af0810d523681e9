// gportd's configuration: every setting, its default, and its JSON key.
//
// The file is JSON with comments allowed (default /etc/gportd/gportd.json);
// see config/gportd.json for the annotated example and docs/configuration.md
// for the reference. Command-line options override the file.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "gport/contract/limits.hpp"
#include "gport/contract/names.hpp"

namespace gport::config {

using Millis = std::chrono::milliseconds;

struct SerialConfig {                    // "serial"
    std::string device = "/dev/gimbal";  // "device"
    unsigned baud = 115200;              // "baud": one of the standard termios rates
};

struct SocketConfig {                             // "socket"
    std::string path = contract::kDefaultSocket;  // "path"
    unsigned mode = 0660;                         // "mode": octal string such as "0660"
    std::string group;                            // "group": name; empty keeps the daemon's group
    std::size_t line_limit = 64 * 1024;           // "line_limit": bytes per request line
    std::size_t max_clients = 128;                // "max_clients"
    std::size_t queue_limit = 256;                // "queue_limit": outbound lines per client
    // Slots and fairness (docs/configuration.md says why these defaults).
    std::size_t max_clients_per_uid = 64;    // "max_clients_per_uid"
    std::size_t reserved_command_slots = 8;  // "reserved_command_slots": kept for commanders
    Millis idle_timeout{300000};             // "idle_timeout_ms": unsubscribed and quiet
    unsigned max_requests_per_s = 200;  // "max_requests_per_s": per client, batch members count
};

struct KeepaliveConfig {            // "keepalive"
    double rate_hz = 10.0;          // "rate_hz": re-send rate of speed commands
    Millis default_duration{1000};  // "default_duration_ms"
    Millis max_duration{60000};     // "max_duration_ms"
};

struct LinkConfig {                 // "link"
    Millis stale_after{500};        // "stale_ms": no attitude this long -> stale
    Millis reconnect_initial{250};  // "reconnect_initial_ms": first reopen delay
    Millis reconnect_max{5000};     // "reconnect_max_ms": backoff cap
};

struct RequestConfig {     // "requests": settings requests to the gimbal
    Millis timeout{300};   // "timeout_ms": per attempt
    unsigned retries = 2;  // "retries": attempts after the first
};

struct AccessConfig {  // "access"
    // Peers allowed to command the gimbal. Both empty: every peer that can
    // connect may command (the socket's mode is the only gate). Root and the
    // daemon's own uid may always command.
    std::vector<uid_t> control_uids;  // "control_uids"
    std::vector<gid_t> control_gids;  // "control_gids"
    // Peers allowed to publish the vehicle's state (publish_vehicle), which
    // stamps every capture: a spoofed position is a wrong map. Root and the
    // daemon's own uid always may. nullopt (the key absent): the user
    // kVehicleUser when it exists (the package creates it), resolved when
    // the configuration is loaded (config::load_config); else nobody else.
    std::optional<std::vector<uid_t>> vehicle_uids;  // "vehicle_uids"
};
// The user the packaged gport-mavlink runs as: access.vehicle_uids' default.
inline constexpr char kVehicleUser[] = "gport-mavlink";

// Real-time scheduling, applied once at start (like chronyd's -P and -m);
// refusal is a warning, never fatal (docs/configuration.md, "realtime").
constexpr int kMaxRealtimePriority = 99;
struct RealtimeConfig {        // "realtime"
    int priority = 0;          // "priority": 0 = normal scheduling, 1-99 = SCHED_FIFO
    bool lock_memory = false;  // "lock_memory": mlockall(MCL_CURRENT | MCL_FUTURE)
};

struct LogConfig {               // "log"
    std::string level = "info";  // "level": trace, debug, info, warn, error, critical, off
};

// Soft limits on motion, in degrees; the core refuses (or, on request, clamps)
// commands beyond them. The defaults are the protocol's whole range
// (contract::kMaxDegrees): no limit.
using contract::kMaxDegrees;
constexpr double kMaxBrakingMargin = 90.0;  // limits.braking_margin_deg: 0 to this

struct AxisRange {              // "roll", "pitch", "yaw"
    double min = -kMaxDegrees;  // "min"
    double max = kMaxDegrees;   // "max": greater than min
    bool operator==(const AxisRange&) const = default;
};

struct LimitsConfig {                // "limits"
    AxisRange roll;                  // "roll": angle commands
    AxisRange pitch;                 // "pitch"
    AxisRange yaw;                   // "yaw"
    double max_speed = kMaxDegrees;  // "max_speed": °/s, every axis, speed commands
    // "braking_margin_deg": how far before a limit a speed motion's axis is
    // stopped, beyond the distance it covers until the next check
    // (docs/configuration.md says how the whole braking distance is made).
    double braking_margin_deg = 1.0;
};

// What the daemon sends when a speed motion ends without its owner's stop
// (docs/configuration.md, "failsafe"). kStop is zero speed; kHold adds an
// angle command to the latest hall (joint) angles; kCenter adds the centre
// command. The zero speed always goes first.
enum class Failsafe { kStop, kHold, kCenter };

// "stop", "hold", "center".
constexpr const char* to_string(Failsafe f) {
    switch (f) {
        case Failsafe::kHold:
            return "hold";
        case Failsafe::kCenter:
            return "center";
        case Failsafe::kStop:
            break;
    }
    return "stop";
}

struct FailsafeConfig {                        // "failsafe"
    Failsafe on_owner_gone = Failsafe::kStop;  // "on_owner_gone": the owner disconnected
    Failsafe on_shutdown = Failsafe::kStop;    // "on_shutdown": SIGTERM / shutdown
    Failsafe on_link_lost = Failsafe::kStop;   // "on_link_lost": "stop" or "center", never "hold"
};

// Tracked angle and centre motions (docs/configuration.md, "motion").
struct MotionConfig {            // "motion"
    double tolerance_deg = 0.5;  // "tolerance_deg": reached within this of the target
    Millis timeout{10000};       // "timeout_ms": not reached by then -> ends "timeout"
    Millis stall{2000};          // "stall_ms": no progress for this long -> "stalled"; 0: off
};

// The capture log (docs/configuration.md, "captures"; docs/operations.md).
struct CapturesConfig {                      // "captures"
    std::string dir;                         // "dir": empty = $STATE_DIRECTORY, else memory only
    std::uint64_t max_file_bytes = 1048576;  // "max_file_bytes": rotate past this
    int keep_files = 4;                      // "keep_files": captures.jsonl and .1 ... .N-1
};

// Camera commands (docs/configuration.md, "camera"): photo and record
// toggles reach the camera through the gimbal, which cannot take more than a
// few a second; a flood would only fill the serial line ahead of a stop.
//
// Each capture is stamped with the vehicle's state at the camera frame's
// instant on the line plus shutter_delay (docs/api.md, "The vehicle"); a
// position older than max_position_age at that instant leaves it untagged.
constexpr int kMaxShutterDelayMs = 5000;
struct CameraConfig {               // "camera"
    double max_commands_per_s = 5;  // "max_commands_per_s": photos and record toggles
    Millis shutter_delay{0};        // "shutter_delay_ms": 0 to kMaxShutterDelayMs
    Millis max_position_age{1000};  // "max_position_age_ms": 100 to 10000
};

struct Config {
    SerialConfig serial;
    SocketConfig socket;
    KeepaliveConfig keepalive;
    LinkConfig link;
    RequestConfig requests;
    AccessConfig access;
    LogConfig log;
    RealtimeConfig realtime;
    LimitsConfig limits;
    FailsafeConfig failsafe;
    MotionConfig motion;
    CapturesConfig captures;
    CameraConfig camera;
    bool simulate = false;  // command line only: --simulate
};

}  // namespace gport::config
