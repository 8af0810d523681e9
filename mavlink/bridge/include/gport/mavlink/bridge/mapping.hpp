// gport-mavlink's mapping between MAVLink's gimbal protocol v2 and gportd's
// API: pure functions and small state machines, no I/O (docs/mavlink.md,
// "What is mapped").
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include "gport/client/types.hpp"
#include "gport/mavlink/frame.hpp"
#include "gport/mavlink/message_types.hpp"

namespace gport::mavlink::bridge {

// Per-axis sign flips between G-Port degrees and MAVLink degrees (default
// identity: roll right, pitch up, yaw right positive on both sides).
struct Invert {
    bool roll = false;
    bool pitch = false;
    bool yaw = false;
};

// Applies the flips (the same both ways: a flip is its own inverse).
client::Axes apply(const Invert& invert, const client::Axes& axes);

// ---- GIMBAL_DEVICE_SET_ATTITUDE -> a gportd command --------------------------

struct AngleCommand {  // gportd `angle`, degrees, vehicle frame
    client::Axes target{};
};
struct SpeedCommand {  // gportd `speed`, degrees per second
    client::Axes speed{};
};
struct CenterCommand {};      // gportd `center` (RETRACT or NEUTRAL)
struct IdleCommand {};        // all NaN: the manager has no target yet (PX4 streams it)
struct NoCommand {            // nothing to send
    std::string_view kind{};  // why, in fixed words (one log kind per value: log_limit.hpp)
    std::string reason{};     // why, with the values
};
using Command = std::variant<NoCommand, AngleCommand, SpeedCommand, CenterCommand, IdleCommand>;

// True when the message asks for earth-frame yaw: YAW_IN_EARTH_FRAME, or
// (the protocol's older convention) YAW_LOCK without either frame flag.
bool yaw_in_earth_frame(std::uint16_t flags);

// True for the null rotation, [±1, 0, 0, 0] exactly.
bool is_identity(const Quaternion& q);

// True when a set-attitude message's rates are taken over its quaternion:
// the quaternion is the null rotation and at least one rate is finite.
// PX4's gimbal manager sends DO_GIMBAL_MANAGER_PITCHYAW with NaN angles (a
// rate command) as q = [1, 0, 0, 0] plus the rates (its input_mavlink
// turns NaN angles into 0), where the protocol asks for a NaN quaternion;
// a manager that wants the centre sends no rates (docs/mavlink.md, "Rates
// and the quaternion").
bool rates_win(const GimbalDeviceSetAttitude& message);

// The command for a set-attitude message. `vehicle_yaw_deg` is the
// vehicle's yaw (AUTOPILOT_STATE_FOR_GIMBAL_DEVICE, else the autopilot's
// ATTITUDE: vehicle_yaw.hpp), needed to turn an earth-frame yaw into a
// vehicle-frame one; without it such a target is a NoCommand. A NaN rate
// axis counts as 0; rates win over a null-rotation quaternion (rates_win);
// all rates NaN with a NaN quaternion is an IdleCommand.
Command map_set_attitude(const GimbalDeviceSetAttitude& message, const Invert& invert,
                         std::optional<double> vehicle_yaw_deg);

// ---- the change filter -------------------------------------------------------

// Passes an angle target only when no target was sent yet or one axis moved
// by more than `threshold_deg` (MAVLink's float quaternion resolves about
// 0.01° once turned into the G-Port's 0.01° frames).
class AngleFilter {
  public:
    explicit AngleFilter(double threshold_deg = 0.01) : threshold_(threshold_deg) {}
    // True (and remembers the target) when it should be sent.
    bool pass(const client::Axes& target);
    // Forgets the last target (another kind of command ran, or gportd reconnected).
    void reset() { last_.reset(); }

  private:
    double threshold_;
    std::optional<client::Axes> last_;
};

// ---- addressing ------------------------------------------------------------------

// True when a message with these targets is for us (or broadcast: 0).
bool addressed_to(std::uint8_t target_system, std::uint8_t target_component, std::uint8_t sysid,
                  std::uint8_t compid);

// ---- status --------------------------------------------------------------------

struct Health {
    bool gportd_connected = false;
    std::string link_state{};   // gportd's link: "up", "stale", "down" ("" unknown)
    bool manager_seen = false;  // our vehicle's autopilot heartbeat within the last 3 s
};

// HEARTBEAT system_status: ACTIVE when gportd is reached and its link is
// up, CRITICAL otherwise.
std::uint8_t system_status(const Health& health);

// GIMBAL_DEVICE_ATTITUDE_STATUS failure_flags: COMMS_ERROR when the link
// is stale or down, COMMS_ERROR | SOFTWARE_ERROR when gportd is
// unreachable, NO_MANAGER without a manager.
std::uint32_t failure_flags(const Health& health);

// What the attitude status needs besides the health.
struct AttitudeInputs {
    std::optional<client::AttitudeSample> sample{};
    std::optional<double> vehicle_yaw_deg{};       // from AUTOPILOT_STATE_FOR_GIMBAL_DEVICE
    std::optional<double> vehicle_yaw_rate_dps{};  // its angular_velocity_z, if sent
    std::uint16_t mode_flags = 0;                  // lock/retract/neutral of the last command
    std::uint32_t time_boot_ms = 0;
    std::uint8_t target_system = 0;
    std::uint8_t target_component = 0;
};

// The status message: quaternion from IMU roll and pitch and hall yaw
// (vehicle frame), angular velocity from the rates (IMU x/y, hall yaw) or NaN
// without them, delta_yaw (the vehicle's yaw) or NaN. Without a sample the
// quaternion is NaN.
GimbalDeviceAttitudeStatus make_attitude_status(const AttitudeInputs& inputs, const Health& health,
                                                const Invert& invert);

// The G-Port's mechanical range (docs/simulator.md, the device's model;
// yaw ±170° was seen on the device, issue 31), in degrees.
struct GportRange {
    client::AxisRange roll{-45, 45};
    client::AxisRange pitch{-90, 90};
    client::AxisRange yaw{-170, 170};
};
inline constexpr GportRange kGportRange{};

// The GIMBAL_DEVICE_INFORMATION gport-mavlink sends. The angle limits are
// gportd's soft limits (`limits` method) in radians, flipped with `invert`;
// the G-Port's mechanical range (kGportRange) for an axis without one (the
// protocol's ±327.67°) or before gportd answered: an autopilot that knows
// the range does not aim beyond it (ArduPilot kept ±180° with NaN).
GimbalDeviceInformation make_information(std::uint32_t time_boot_ms,
                                         const std::optional<client::Limits>& limits,
                                         const Invert& invert);

}  // namespace gport::mavlink::bridge
