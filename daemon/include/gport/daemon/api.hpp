// gport::daemon::Api — what the daemon core offers its clients. The IPC layer
// calls these methods with the client's identity and turns the results and
// events into JSON; it never touches the serial port. Core implements it;
// tests and fuzzers may implement it with a fake.
//
// Every method runs on the event loop's thread. Commands are checked in this
// order: parameters (kInvalidParams), access (kPermission), arbitration
// (kBusy), device open (kLinkDown).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gport/config/config.hpp"
#include "gport/contract/counters.hpp"
#include "gport/daemon/events.hpp"
#include "gport/daemon/outcome.hpp"
#include "gport/daemon/vehicle.hpp"

namespace gport::daemon {

struct Settings {
    std::uint8_t dead_zone = 0;
    std::uint8_t follow_speed = 0;
    bool inverted = false;
};

// The fields a set_settings request changes; the rest stay as the gimbal has them.
struct SettingsChange {
    std::optional<std::uint8_t> dead_zone;
    std::optional<std::uint8_t> follow_speed;
    std::optional<bool> inverted;
};

// What gportd assumes about the camera's recording. The gimbal never reports
// it: 0x86 value 1 only toggles. It starts unknown, flips with every toggle
// that went out (unknown stays unknown), and is unknown again whenever the
// device (re)opens, since the gimbal may have been power-cycled meanwhile.
enum class RecordingState { kUnknown, kOff, kOn };

constexpr std::string_view to_string(RecordingState state) {
    switch (state) {
        case RecordingState::kOff:
            return "off";
        case RecordingState::kOn:
            return "on";
        case RecordingState::kUnknown:
            break;
    }
    return "unknown";
}

// record: no `on` toggles. With `on`, toggles only when the assumed state
// differs; an unknown state is refused (kInvalidParams) unless `force`, which
// toggles and takes `on` as the new state.
struct RecordRequest {
    std::optional<bool> on;
    bool force = false;
};

// When a photo or record toggle took effect, and where the vehicle was:
// the instant its frame's last byte is due on the line (SerialPort::
// due_on_wire), plus camera.shutter_delay_ms; the vehicle's state carried
// to that instant (nullopt: nothing ever published it).
struct CaptureMoment {
    SteadyTime on_wire{};
    SteadyTime instant{};
    std::optional<VehicleStamp> vehicle;
};

struct RecordResult {
    bool sent = false;
    RecordingState recording = RecordingState::kUnknown;
    std::optional<CaptureMoment> moment{};  // when sent
};

struct SpeedStarted {
    Millis duration{0};
    WallTime ends_at{};
    protocol::Axes speed{};              // as sent, after limits.max_speed
    std::vector<std::string> clamped{};  // axes clamped ("roll", "pitch", "yaw")
    std::vector<std::string> braked{};   // axes zeroed: at or near their soft limit
};

struct AngleSent {
    protocol::Axes angle{};              // as sent, after the limits
    std::vector<std::string> clamped{};  // axes clamped ("roll", "pitch", "yaw")
};

// The counters of the status result: the core's part of the contract's
// list (gport/contract/counters.hpp says what each counts).
struct Counters {
#define GPORT_DAEMON_COUNTER(name) std::uint64_t name = 0;
    GPORT_CONTRACT_CORE_COUNTERS(GPORT_DAEMON_COUNTER)
#undef GPORT_DAEMON_COUNTER
};

struct MotionStatus {
    MotionMode mode = MotionMode::kSpeed;
    std::optional<ClientInfo> owner;
    protocol::Axes speed;
    Millis time_left{0};      // speed motions only: to the earlier of its end and its lease's
    protocol::Axes target{};  // angle and centre motions only (0.01°; centre: 0)
    Millis elapsed{0};        // since the motion started
};

// How a tracked angle or centre motion ended: the answer to a `wait`.
struct MotionEnd {
    EndReason reason = EndReason::kReached;
    std::optional<AttitudeSample> attitude;  // the latest sample when it ended, if any
    Millis elapsed{0};                       // from the command to the end
    std::string detail{};                    // kStalled: where the gimbal stopped, else empty
};

// Told once how a tracked motion ended; runs later on the loop, never from
// inside the call that ended the motion.
using MotionEndCallback = std::function<void(const MotionEnd&)>;

// Camera commands (config "camera"): the limit and what it refused.
struct CameraStatus {
    double max_commands_per_s = 0;
    std::uint64_t refused = 0;  // photos and record toggles over the limit since start
};

struct Status {
    LinkState link = LinkState::kDown;
    std::string link_reason;
    std::string device;
    bool device_open = false;
    std::optional<std::string> device_error;  // closed: why the last open failed
    Millis uptime{0};
    std::optional<Millis> attitude_age;
    Counters counters;
    std::optional<MotionStatus> motion;                   // a speed or tracked motion
    std::optional<ClientInfo> controller;                 // holder of acquire(), if any
    RecordingState recording = RecordingState::kUnknown;  // assumed, see RecordingState
    CameraStatus camera;
    std::optional<VehicleStatus> vehicle;  // nullopt: never published nor refused
};

class Api {
  public:
    virtual ~Api() = default;

    virtual void set_observer(CoreObserver* observer) = 0;  // nullptr to detach

    // ---- queries (any client) ----
    virtual Status status() const = 0;
    virtual std::optional<AttitudeSample> latest_attitude() const = 0;
    virtual bool may_command(const ClientInfo& client) const = 0;
    // The configured soft limits (config "limits"), read-only.
    virtual config::LimitsConfig limits() const = 0;
    // The longest duration and lease a speed may ask for
    // (keepalive.max_duration_ms), so that a request is refused naming it.
    virtual Millis max_duration() const = 0;

    // ---- commands ----
    // Speed in 0.01°/s; duration empty means the configured default. A
    // duration above the configured maximum is refused (kInvalidParams).
    // A speed faster than limits.max_speed on any axis is refused
    // (kInvalidParams) or, with `clamp`, clamped to it. A speed from the
    // client that owns the current speed motion updates it (kUpdated, rate
    // limited) instead of replacing it. `lease` (empty: the duration, else 1
    // to the maximum duration) ends the motion with kLeaseExpired (under
    // failsafe.on_owner_gone) when no further speed from its owner arrives
    // within it. An axis at, beyond or within the braking distance of a
    // soft limit it moves towards is sent as 0 (SpeedStarted::braked); an
    // axis moving towards a narrowed limit needs a fresh attitude
    // (kLinkDown otherwise). The running motion is braked the same way on
    // every attitude sample (docs/api.md, "Braking at the soft limits").
    virtual Outcome<SpeedStarted> speed(const ClientInfo& client, protocol::Axes speed,
                                        std::optional<Millis> duration, bool clamp = false,
                                        std::optional<Millis> lease = std::nullopt) = 0;
    virtual Outcome<Done> stop(const ClientInfo& client) = 0;
    // Angle in 0.01°. A target outside the soft limits (limits.roll/pitch/yaw)
    // is refused (kInvalidParams) or, with `clamp`, clamped into them.
    // angle and center start a tracked motion (MotionTracker): it ends when
    // the hall angles reach the target, at motion.timeout_ms, or when
    // something else ends it. `on_end`, when given, makes the caller a
    // waiting owner: it is called exactly once when the motion ends (only if
    // the command succeeded), and the owner's departure ends the motion
    // (kOwnerGone, with the failsafe). Without it the motion outlives its owner.
    virtual Outcome<AngleSent> angle(const ClientInfo& client, protocol::Axes angle,
                                     bool clamp = false, MotionEndCallback on_end = {}) = 0;
    // The centre is 0/0/0 clamped into the soft limits: where 0 lies outside
    // an axis's range, that axis aims at its nearest limit instead and an
    // angle frame is sent in place of the centre command (AngleSent::clamped
    // names the axes). A tracked motion of mode kCenter either way.
    virtual Outcome<AngleSent> center(const ClientInfo& client, MotionEndCallback on_end = {}) = 0;
    virtual Outcome<Done> lock(const ClientInfo& client) = 0;
    virtual Outcome<CaptureMoment> photo(const ClientInfo& client) = 0;
    virtual Outcome<RecordResult> record(const ClientInfo& client, RecordRequest request) = 0;

    // The vehicle's state from a trusted source (access.vehicle_uids, root,
    // the daemon's user): values checked first (kInvalidParams), then who
    // publishes (kPermission), then order and source (VehicleTrack).
    virtual Outcome<Done> publish_vehicle(const ClientInfo& client,
                                          const VehicleReport& report) = 0;

    // Control arbitration: returns the holder after the call.
    virtual Outcome<std::optional<ClientInfo>> acquire(const ClientInfo& client) = 0;
    virtual Outcome<std::optional<ClientInfo>> release(const ClientInfo& client) = 0;

    // Asynchronous: the callback runs later on the loop, exactly once.
    using SettingsCallback = std::function<void(Outcome<Settings>)>;
    virtual void get_settings(const ClientInfo& client, SettingsCallback done) = 0;
    virtual void set_settings(const ClientInfo& client, SettingsChange change,
                              SettingsCallback done) = 0;

    // The client hung up (EOF) or its connection closed: the deadman. Ends
    // its speed motion, or the tracked motion it waits for (kOwnerGone, with
    // failsafe.on_owner_gone), and releases its control at once. Its settings requests
    // still complete (a half-closed client still reads its replies).
    virtual void client_gone(const ClientInfo& client) = 0;
    // The connection is closed for good: nothing more is delivered to it.
    // Its queued settings requests are dropped (their callbacks never run)
    // and anything kept per connection is forgotten. Called after
    // client_gone, once per connection.
    virtual void client_closed(const ClientInfo& client) = 0;
};

}  // namespace gport::daemon
