// Whom gport-mavlink obeys: the trust decision, small and pure, for every
// MAVLink component the program runs (the gimbal, compid 154; a camera
// component, compid 100, reuses it). It sees only who sent a frame
// (its header) and what the frame would do (its concern); signatures are
// checked before it (verifier.hpp), addressing after it (addressed_to).
//
//   sender's system id       commands      vehicle state
//   our vehicle's, from one  ignored (kOwnEcho): our own frames, sent back
//     of our components
//   our vehicle's            obeyed        used
//   a ground station's       obeyed        ignored (kNotVehicle)
//   anyone else's            ignored (kStranger)
//   (vehicle not known yet)  ignored (kNoVehicle)
//
// Commands are GIMBAL_DEVICE_SET_ATTITUDE and COMMAND_LONG; vehicle state
// is what steers us without being a command: HEARTBEAT ("a gimbal manager
// is present"), AUTOPILOT_STATE_FOR_GIMBAL_DEVICE and ATTITUDE (the
// vehicle's yaw) and GLOBAL_POSITION_INT (where a photo was taken).
// Other messages concern nothing we act on; they count as trusted from the
// vehicle and the ground stations (e.g. for choosing the reply peer).
//
// The vehicle's system id is configured (default 1, ArduPilot's and PX4's
// default) or, with `auto`, adopted from the first autopilot HEARTBEAT
// (not MAV_TYPE_GCS, not MAV_AUTOPILOT_INVALID). Adoption believes whoever
// speaks first, so it is spoofable: documented as such.
#pragma once

#include <bitset>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "gport/mavlink/frame.hpp"
#include "gport/mavlink/message_types.hpp"

namespace gport::mavlink::bridge {

enum class Concern { kCommand, kVehicleState, kOther };

// What a message would do, by its id.
Concern concern_of(std::uint32_t msgid);

enum class TrustVerdict {
    kTrusted,
    kNoVehicle,   // auto mode before the vehicle's heartbeat: nothing is obeyed
    kNotVehicle,  // a ground station's frame claiming vehicle state
    kStranger,    // a system id that is neither the vehicle nor a ground station
    // The vehicle's system id with one of our own component ids: our own
    // frames sent back (a routing loop, or a replay: a signed one passes the
    // signature check as a stream never received), never a peer's.
    kOwnEcho,
};

std::string_view to_string(TrustVerdict verdict);

struct TrustPolicy {
    std::optional<std::uint8_t> vehicle = 1;  // nullopt: adopt (auto)
    std::bitset<256> ground_stations{};       // system ids; 0 is never one
    std::bitset<256> own_components{};        // our component ids (154, 100)
};

class Trust {
  public:
    explicit Trust(const TrustPolicy& policy);

    // In auto mode, adopts the sender's system id when this is the first
    // autopilot heartbeat; returns true when it did.
    bool on_heartbeat(const Header& from, const Heartbeat& heartbeat);

    TrustVerdict judge(const Header& from, Concern concern) const;
    TrustVerdict judge(const Header& from, std::uint32_t msgid) const {
        return judge(from, concern_of(msgid));
    }

    std::optional<std::uint8_t> vehicle() const { return vehicle_; }
    bool adopts() const { return adopts_; }
    bool is_ground_station(std::uint8_t sysid) const { return ground_stations_.test(sysid); }

  private:
    std::optional<std::uint8_t> vehicle_;
    bool adopts_;
    std::bitset<256> ground_stations_;
    std::bitset<256> own_components_;
};

// A heartbeat that comes from a flight controller (a gimbal manager): not a
// ground station's (MAV_TYPE_GCS), not a component's that is no autopilot
// (MAV_AUTOPILOT_INVALID: gimbals, cameras, companions).
bool is_autopilot(const Heartbeat& heartbeat);

}  // namespace gport::mavlink::bridge
