// The MAVLink checksum: CRC-16/MCRF4XX, which MAVLink calls X.25.
//
//   polynomial 0x1021 reflected (0x8408), register initialised to 0xFFFF,
//   input and output reflected, no final XOR. On the wire little-endian.
//
// A frame's checksum covers every byte after the start byte up to the end
// of the payload, then one more byte: the message's CRC_EXTRA, a digest of
// its name and field layout (crc_extra_of() below), so two ends that
// disagree on a layout reject each other's frames.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

namespace gport::mavlink {

inline constexpr std::uint16_t kCrcInit = 0xFFFF;

// One byte into the register, exactly MAVLink's crc_accumulate().
constexpr std::uint16_t crc_accumulate(std::uint8_t byte, std::uint16_t crc) {
    auto tmp = static_cast<std::uint8_t>(byte ^ (crc & 0xFFU));
    tmp = static_cast<std::uint8_t>(tmp ^ (tmp << 4));
    return static_cast<std::uint16_t>((crc >> 8) ^ (tmp << 8) ^ (tmp << 3) ^ (tmp >> 4));
}

constexpr std::uint16_t crc_accumulate(std::span<const std::uint8_t> bytes, std::uint16_t crc) {
    for (std::uint8_t b : bytes) {
        crc = crc_accumulate(b, crc);
    }
    return crc;
}

constexpr std::uint16_t crc_accumulate(std::string_view text, std::uint16_t crc) {
    for (char c : text) {
        crc = crc_accumulate(static_cast<std::uint8_t>(c), crc);
    }
    return crc;
}

constexpr std::uint16_t crc_calculate(std::span<const std::uint8_t> bytes) {
    return crc_accumulate(bytes, kCrcInit);
}

}  // namespace gport::mavlink
