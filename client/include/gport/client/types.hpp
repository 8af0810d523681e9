// The typed results and notifications of libgport-client: plain aggregates
// mirroring docs/api.md. Units: degrees, degrees per second, milliseconds;
// times in seconds since the epoch.
//
// ABI: these structs are part of the library's ABI. Adding, removing or
// reordering a member changes it and bumps the SONAME (libgport-client.so.N).
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "gport/contract/counters.hpp"

namespace gport::client {

using Milliseconds = std::chrono::milliseconds;

struct Axes {
    double roll = 0;
    double pitch = 0;
    double yaw = 0;
};

// A client of gportd as the daemon reports it (owner, controller, yourself).
struct Peer {
    std::int64_t id = 0;
    std::int64_t pid = 0;
    std::int64_t uid = 0;
    std::int64_t gid = 0;
};

struct ImuRates {
    double x = 0;
    double y = 0;
    double z = 0;
};

// Angular rates, sent only by gimbals with the 24-byte attitude frame.
struct Rates {
    Axes hall{};     // °/s
    ImuRates imu{};  // °/s
};

// One 0x87 attitude frame: the `attitude` method's result and notification.
struct AttitudeSample {
    std::uint64_t seq = 0;  // frames since the daemon started
    double time = 0;        // receive time, seconds since the epoch (µs resolution)
    Axes imu{};
    Axes hall{};
    std::optional<Rates> rates{};
    std::optional<std::int64_t> age_ms{};  // `attitude()` only: how old the sample is
    std::uint64_t dropped = 0;             // notifications: samples this client lost so far
};

struct Link {
    std::string state{};  // "up", "stale" or "down"
    std::string reason{};
};

// The running motion (`Status::motion`).
struct Motion {
    std::string mode{};  // "speed", "angle", "center" or "lock"
    std::optional<Peer> owner{};
    std::optional<Axes> speed{};   // speed motions
    std::optional<Axes> target{};  // angle / centre motions
    std::optional<std::int64_t> time_left_ms{};
    std::optional<std::int64_t> elapsed_ms{};
};

// The status result's counters: the fields of gport/contract/counters.hpp
// (frames_in, bytes_in, ... settings_timeouts, dropped_notifications), each
// a std::uint64_t, in that order.
struct Counters {
#define GPORT_CLIENT_COUNTER(name) std::uint64_t name = 0;
    GPORT_CONTRACT_COUNTERS(GPORT_CLIENT_COUNTER)
#undef GPORT_CLIENT_COUNTER
};

struct Status {
    int api_version = 0;
    std::string daemon_version{};
    Link link{};
    std::string device{};
    bool device_open = false;
    std::optional<std::string> device_error{};  // closed: why the last open failed
    std::int64_t uptime_ms = 0;
    std::optional<std::int64_t> attitude_age_ms{};  // empty before the first sample
    Counters counters{};
    std::int64_t clients = 0;
    std::uint64_t dropped_notifications = 0;
    std::optional<Motion> motion{};
    std::optional<Peer> controller{};
    std::string recording{};  // assumed state: "on", "off" or "unknown"
    Peer self{};              // this connection
    std::uint64_t self_dropped = 0;
};

struct SpeedOptions {
    std::optional<Milliseconds> duration{};  // default: keepalive.default_duration_ms
    std::optional<Milliseconds> lease{};     // default: the duration
    bool clamp = false;                      // clamp to limits.max_speed instead of refusing
};

struct SpeedResult {
    std::int64_t duration_ms = 0;
    double ends_at = 0;  // seconds since the epoch
    Axes speed{};        // as sent, after clamping
    std::vector<std::string> clamped{};
};

struct AngleOptions {
    bool clamp = false;  // clamp into limits.* instead of refusing
    bool wait = false;   // reply only when the motion ends (fills `ended`)
};

struct CenterOptions {
    bool wait = false;
};

// How a tracked angle or centre motion ended (`wait: true`).
struct MotionEnd {
    std::string reason{};  // reached, stalled, timeout, replaced, stop, owner_gone, ...
    std::optional<AttitudeSample> attitude{};
    std::int64_t elapsed_ms = 0;
    std::string
        detail{};  // stalled: where the gimbal stopped ("stalled at pitch -90.00 ..."), else
};

struct AngleResult {
    bool sent = false;
    Axes angle{};  // the target sent, after clamping
    std::vector<std::string> clamped{};
    std::optional<MotionEnd> ended{};
};

struct CenterResult {
    bool sent = false;
    std::optional<MotionEnd> ended{};
};

// What gportd's capture log recorded for a photo or a record toggle that
// reached the wire (the `capture` member of the reply; absent from a gportd
// without the log, and when nothing was sent).
struct Capture {
    std::uint64_t index = 0;
    std::optional<std::uint64_t> utc_us{};  // wall-clock time, µs since 1970
    std::string kind{};                     // photo, record_start, record_stop, record_toggle
};

// `meta` for photo and record: the text of a JSON object (at most 1 KiB
// compact) stored with the capture; empty: none sent.
struct CaptureOptions {
    std::string meta{};
};

struct PhotoResult {
    std::optional<Capture> capture{};
};

// The attitude gportd logged with a capture (its `capture.attitude`):
// IMU and hall angles in degrees and how old the sample was. New in 1.4.0
// beside Capture, not in it: a member added to Capture would change the
// layout of PhotoResult and RecordResult (SOVERSION 1).
struct CaptureAttitude {
    Axes imu{};
    Axes hall{};
    std::int64_t age_ms = 0;
};

// async_photo_report's result (1.4.0): the capture and its attitude (none
// when gportd had no sample, or is older and does not send one).
struct PhotoReport {
    std::optional<Capture> capture{};
    std::optional<CaptureAttitude> attitude{};
};

struct RecordResult {
    bool sent = false;
    std::string recording{};  // "on", "off" or "unknown" after the call
    std::optional<Capture> capture{};
};

// One capture of gportd's log as captures() lists it and the "capture"
// topic announces it (1.5.0; new beside Capture, which keeps its layout).
struct CaptureEntry {
    Capture capture{};
    std::optional<CaptureAttitude> attitude{};  // none before the first sample
    std::string meta{};                         // the meta object as compact JSON; empty: none
    std::optional<Peer> client{};               // who asked for it
    std::string client_name{};                  // its process name, as gportd saw it
};

// One page of captures(since, limit) (1.5.0): oldest first, bounded by the
// limit and by gportd's 64 KiB; when `more`, ask again from `next`.
struct CapturesPage {
    std::vector<CaptureEntry> captures{};
    bool more = false;
    std::uint64_t next = 0;
};

struct Control {
    std::optional<Peer> controller{};
    bool you_hold_control = false;
};

struct Settings {
    int dead_zone = 0;
    int follow_speed = 0;
    bool inverted = false;
};

// set_settings: only the fields given change (at least one).
struct SettingsChange {
    std::optional<int> dead_zone{};
    std::optional<int> follow_speed{};
    std::optional<bool> inverted{};
};

// The `limits` method: gportd's configured soft limits (config "limits").
struct AxisRange {
    double min = 0;
    double max = 0;
};

struct Limits {
    AxisRange roll{};
    AxisRange pitch{};
    AxisRange yaw{};
    double max_speed = 0;  // °/s
    double braking_margin_deg = 0;
};

// subscribe() with options. shared_memory: attitude comes from gportd's
// shared-memory attitude channel (AttitudeChannel) instead of the socket,
// through the same callbacks and next_notification(); max_rate_hz does not
// apply to it (every sample is offered; a slow reader skips some).
struct SubscribeOptions {
    std::optional<double> max_rate_hz{};
    bool shared_memory = false;
};

struct Subscription {
    std::vector<std::string> topics{};
    std::optional<double> max_rate_hz{};
};

// Notifications (topics "attitude", "link", "motion").
struct LinkEvent {
    std::string state{};
    std::string reason{};
};

struct MotionEvent {
    std::string change{};  // started, replaced, updated, ended
    std::string mode{};    // speed, angle, center, lock
    std::optional<Peer> owner{};
    std::optional<Axes> speed{};   // speed motions
    std::optional<Axes> target{};  // angle / centre motions
    std::optional<std::int64_t> duration_ms{};
    std::optional<std::string> reason{};  // ended / updated
    std::vector<std::string> braked{};    // updated with reason "limit"
};

using Notification = std::variant<AttitudeSample, LinkEvent, MotionEvent>;

// publish_vehicle's report (1.10.0; docs/api.md, "The vehicle"): a position
// at the autopilot's boot time, its UTC (SYSTEM_TIME), or both. Only a
// trusted source may publish (gportd's access.vehicle_uids).
struct VehiclePosition {
    std::uint32_t boot_ms = 0;  // the autopilot's boot time of the sample
    double lat = 0;             // degrees, WGS84
    double lon = 0;
    double alt_msl_m = 0;
    std::optional<double> alt_rel_m{};
    std::array<double, 3> velocity_ned{0, 0, 0};  // m/s
    std::optional<double> heading_deg{};          // 0 to 360
    std::optional<double> yaw_rate_dps{};         // clockwise seen from above
    std::optional<int> fix{};                     // GPS_FIX_TYPE
    std::optional<double> h_acc_m{};
    std::optional<double> v_acc_m{};
    std::optional<int> satellites{};
};

struct VehicleTime {
    std::uint32_t boot_ms = 0;
    std::int64_t utc_us = 0;  // SYSTEM_TIME's time_unix_usec
};

struct VehicleReport {
    std::optional<VehiclePosition> position{};
    std::optional<VehicleTime> time{};
};

// The vehicle where and when a capture was taken, as gportd stamped it
// (1.10.0): tagged with the position carried to the capture's instant, or
// untagged and why. utc_us is the autopilot's UTC at the instant.
struct CaptureVehicle {
    bool tagged = false;
    std::string why{};
    std::optional<std::int64_t> utc_us{};
    double lat = 0;
    double lon = 0;
    double alt_msl_m = 0;
    std::optional<double> alt_rel_m{};
    std::array<double, 3> velocity_ned{0, 0, 0};
    std::optional<double> heading_deg{};
    std::optional<double> h_acc_m{};
    std::optional<double> v_acc_m{};
    std::optional<int> fix{};
    std::optional<int> satellites{};
    std::int64_t age_ms = 0;
};

// A capture's moment (1.10.0): when its frame's last byte was due on the
// line and the instant stamped (that plus camera.shutter_delay_ms), on the
// clock of the capture's mono_us; the vehicle then (none: gportd had no
// vehicle source, or predates the stamp).
struct CaptureStamp {
    std::optional<std::int64_t> line_mono_us{};
    std::optional<std::int64_t> shutter_mono_us{};
    std::optional<CaptureVehicle> vehicle{};
};

}  // namespace gport::client
