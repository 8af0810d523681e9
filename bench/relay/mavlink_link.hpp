// The benchmark's MAVLink peers of gport-mavlink: UDP sockets on loopback
// sending to its udpin port, and the frames they send (gport::mavlink's
// codec): the autopilot's heartbeat and rates, a ground station's camera
// commands and angle targets.
#pragma once

#include <netinet/in.h>

#include <cstdint>
#include <functional>
#include <span>

#include "../e2e/posix.hpp"
#include "gport/mavlink/messages.hpp"

namespace gport::bench::relay {

namespace gm = gport::mavlink;

inline constexpr std::uint8_t kVehicle = 1;          // --sysid 1: the autopilot's system
inline constexpr std::uint8_t kGroundStation = 255;  // --gcs-sysid 255
inline constexpr std::uint8_t kGcsComponent = 190;   // MAV_COMP_ID_MISSIONPLANNER

// A UDP socket on 127.0.0.1 sending as one MAVLink system and component.
class MavlinkPeer {
  public:
    MavlinkPeer(unsigned port, std::uint8_t sysid, std::uint8_t compid);
    void send(const gm::Message& message);
    // Decodes every datagram waiting; `each` gets each message. Returns how many datagrams.
    std::uint64_t drain(const std::function<void(const gm::Message&, std::uint8_t compid)>& each);
    std::uint64_t drain() {
        return drain([](const gm::Message&, std::uint8_t) {});
    }

  private:
    Fd fd_;
    sockaddr_in to_{};
    std::uint8_t sysid_;
    std::uint8_t compid_;
    std::uint8_t seq_ = 0;
};

// A free UDP port on 127.0.0.1 (bound and released: another process may take it).
unsigned free_udp_port();

gm::Heartbeat autopilot_heartbeat();
// GIMBAL_DEVICE_SET_ATTITUDE with a NaN quaternion and a yaw rate (rad/s) to
// the gimbal: a speed; 0 is a stop.
gm::GimbalDeviceSetAttitude yaw_rate(float rad_s);
// GIMBAL_DEVICE_SET_ATTITUDE to an angle (degrees), rates NaN.
gm::GimbalDeviceSetAttitude angle_target(double roll, double pitch, double yaw);
// COMMAND_LONG `command` to the camera component with these params.
gm::CommandLong camera_command(std::uint16_t command, int param_index = -1, float value = 0);

}  // namespace gport::bench::relay
