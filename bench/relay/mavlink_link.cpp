#include "mavlink_link.hpp"

#include <arpa/inet.h>
#include <sys/socket.h>

#include <array>
#include <limits>
#include <stdexcept>

#include "gport/mavlink/attitude.hpp"
#include "gport/mavlink/decoder.hpp"
#include "gport/mavlink/enums.hpp"

namespace gport::bench::relay {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

sockaddr_in loopback(unsigned port) {
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    address.sin_port = htons(static_cast<std::uint16_t>(port));
    return address;
}

Fd bound_udp() {
    Fd fd(::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK, 0));
    const sockaddr_in local = loopback(0);
    if (!fd.valid() || ::bind(fd.get(), reinterpret_cast<const sockaddr*>(&local), sizeof local)) {
        throw std::runtime_error("cannot bind a UDP socket on 127.0.0.1");
    }
    return fd;
}

}  // namespace

MavlinkPeer::MavlinkPeer(unsigned port, std::uint8_t sysid, std::uint8_t compid)
    : fd_(bound_udp()), to_(loopback(port)), sysid_(sysid), compid_(compid) {}

void MavlinkPeer::send(const gm::Message& message) {
    const auto frame = gm::encode(message, {seq_++, sysid_, compid_});
    const auto bytes = frame.bytes();
    ::sendto(fd_.get(), bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&to_),
             sizeof to_);
}

std::uint64_t MavlinkPeer::drain(
    const std::function<void(const gm::Message&, std::uint8_t)>& each) {
    std::array<std::uint8_t, 2048> buffer{};
    std::uint64_t n = 0;
    gm::Decoder decoder;
    for (;;) {
        const ssize_t got = ::recv(fd_.get(), buffer.data(), buffer.size(), 0);
        if (got <= 0) {
            return n;
        }
        ++n;
        decoder.feed(std::span<const std::uint8_t>(buffer.data(), static_cast<std::size_t>(got)),
                     [&](const gm::FrameView& frame) {
                         if (auto message = gm::decode(frame)) {
                             each(*message, frame.header.compid);
                         }
                     });
    }
}

unsigned free_udp_port() {
    const Fd fd = bound_udp();
    sockaddr_in bound{};
    socklen_t size = sizeof bound;
    ::getsockname(fd.get(), reinterpret_cast<sockaddr*>(&bound), &size);
    return ntohs(bound.sin_port);
}

gm::Heartbeat autopilot_heartbeat() {
    gm::Heartbeat heartbeat;
    heartbeat.type = 2;       // quadrotor
    heartbeat.autopilot = 3;  // ArduPilot
    heartbeat.system_status = gm::mav_state::kActive;
    return heartbeat;
}

gm::GimbalDeviceSetAttitude yaw_rate(float rad_s) {
    gm::GimbalDeviceSetAttitude set;
    set.q = {kNaN, kNaN, kNaN, kNaN};
    set.angular_velocity_x = 0;
    set.angular_velocity_y = 0;
    set.angular_velocity_z = rad_s;
    set.target_system = kVehicle;
    set.target_component = gm::mav_comp_id::kGimbal;
    return set;
}

gm::GimbalDeviceSetAttitude angle_target(double roll, double pitch, double yaw) {
    gm::GimbalDeviceSetAttitude set;
    set.q = gm::to_quaternion({roll, pitch, yaw});
    set.angular_velocity_x = set.angular_velocity_y = set.angular_velocity_z = kNaN;
    set.target_system = kVehicle;
    set.target_component = gm::mav_comp_id::kGimbal;
    return set;
}

gm::CommandLong camera_command(std::uint16_t command, int param_index, float value) {
    gm::CommandLong c;
    c.command = command;
    c.target_system = kVehicle;
    c.target_component = gm::mav_comp_id::kCamera;
    if (param_index >= 0) {
        c.param.at(static_cast<std::size_t>(param_index)) = value;
    }
    return c;
}

}  // namespace gport::bench::relay
