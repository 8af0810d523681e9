// Signed frames made by node-mavlink 2.3.0 (an implementation we did not
// write), fixed here as vectors: MavLinkPacketSignature.key(passphrase) is
// SHA-256 of the passphrase (MAVProxy's and Mission Planner's derivation),
// MavLinkProtocolV2(sysid, compid, IFLAG_SIGNED).serialize() then
// .sign(buffer, linkId, key, ms). Made with tests/mavlink/peer (node):
//
//   key = MavLinkPacketSignature.key('gport-mavlink test passphrase')
//   HEARTBEAT (type 2, autopilot 3, base_mode 81, custom_mode 4, status 4,
//     version 3), seq 7, from 1/1, link 3, 2025-01-01T00:00:00.123Z
//   GIMBAL_DEVICE_SET_ATTITUDE (to 1/154, flags 32, q pitch -30°, rates NaN),
//     seq 200, from 255/190, link 0, one second later
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

namespace gport::mavlink::testing {

inline constexpr std::string_view kNodeKeyHex =
    "6b7a18e433b25b83d7424078262de2ed0eaabae9ff142479cfc94bcc57c903b2";
inline constexpr std::string_view kNodeHeartbeatHex =
    "fd090100070101000000040000000203510403dfe4030ce00795b41cc2ec7437f174";
inline constexpr std::uint64_t kNodeHeartbeatTimestamp = 31'561'920'012'300;
inline constexpr std::uint8_t kNodeHeartbeatLink = 3;
inline constexpr std::string_view kNodeSetAttitudeHex =
    "fd200100c8ffbe1c0100ea46773f00000000ed8384be000000000000c07f0000c07f0000c07f2000019a300200"
    "ac660995b41c133dd04830f5";

inline std::vector<std::uint8_t> from_hex(std::string_view hex) {
    std::vector<std::uint8_t> out;
    for (std::size_t i = 0; i + 1 < hex.size(); i += 2) {
        auto nibble = [](char c) {
            return static_cast<std::uint8_t>(c <= '9' ? c - '0' : c - 'a' + 10);
        };
        out.push_back(static_cast<std::uint8_t>(nibble(hex[i]) << 4 | nibble(hex[i + 1])));
    }
    return out;
}

}  // namespace gport::mavlink::testing
