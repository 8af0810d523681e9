// CRC32 of the G-Port protocol (the data field of a frame).
//
//   polynomial 0x04C11DB7, register initialised to 0xFFFFFFFF, no reflection,
//   no final XOR. Each data byte is XORed into the LOW byte of the register,
//   then the register takes four table steps (shift left by 8, XOR the entry
//   of the byte shifted out). On the wire the result is little-endian.
//
// The seed's printed table has misprints (docs/protocol.md); the tables here
// are generated from the polynomial at compile time.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace gport::protocol {

inline constexpr std::uint32_t kCrcPolynomial = 0x04C11DB7U;
inline constexpr std::uint32_t kCrcInit = 0xFFFFFFFFU;

namespace detail {

// The classic MSB-first table: entry v is v·x^32 mod P for the byte v at the top.
constexpr std::array<std::uint32_t, 256> make_crc_table() {
    std::array<std::uint32_t, 256> table{};
    for (std::uint32_t v = 0; v < 256; ++v) {
        std::uint32_t reg = v << 24;
        for (int bit = 0; bit < 8; ++bit) {
            reg = (reg & 0x80000000U) != 0 ? (reg << 1) ^ kCrcPolynomial : reg << 1;
        }
        table[v] = reg;
    }
    return table;
}

inline constexpr auto kCrcTable = make_crc_table();

// Four table steps, one byte at a time: the seed's reference inner loop.
constexpr std::uint32_t four_steps(std::uint32_t reg) {
    for (int i = 0; i < 4; ++i) {
        reg = (reg << 8) ^ kCrcTable[reg >> 24];
    }
    return reg;
}

// Four table steps are linear over GF(2), so they split into one lookup per
// register byte: slice[k][v] = four_steps(v << 8k). The lookups are
// independent of each other, which is what makes this fast.
constexpr std::array<std::array<std::uint32_t, 256>, 4> make_slices() {
    std::array<std::array<std::uint32_t, 256>, 4> slices{};
    for (unsigned k = 0; k < 4; ++k) {
        for (std::uint32_t v = 0; v < 256; ++v) {
            slices[k][v] = four_steps(v << (8 * k));
        }
    }
    return slices;
}

inline constexpr auto kCrcSlices = make_slices();

// Four bytes at a time. With M = four table steps (multiplication by x^32
// mod P), one byte's update is reg' = M(reg ^ b), so four bytes give
//   reg_4 = M^4(reg ^ b0) ^ M^3(b1) ^ M^2(b2) ^ M(b3).
// M^4 of the register splits into one lookup per register byte (kCrcWide);
// each later byte needs one lookup (kCrcLate[j] = M^(3-j)) that does not
// depend on the register, so only one round of lookups per four bytes is on
// the critical path instead of four.
constexpr std::uint32_t m_power(std::uint32_t reg, int power) {
    for (int i = 0; i < power; ++i) {
        reg = four_steps(reg);
    }
    return reg;
}

constexpr std::array<std::array<std::uint32_t, 256>, 4> make_wide() {
    std::array<std::array<std::uint32_t, 256>, 4> wide{};
    for (unsigned k = 0; k < 4; ++k) {
        for (std::uint32_t v = 0; v < 256; ++v) {
            wide[k][v] = m_power(v << (8 * k), 4);
        }
    }
    return wide;
}

constexpr std::array<std::array<std::uint32_t, 256>, 3> make_late() {
    std::array<std::array<std::uint32_t, 256>, 3> late{};
    for (std::size_t j = 0; j < 3; ++j) {
        for (std::uint32_t v = 0; v < 256; ++v) {
            late[j][v] = m_power(v, 3 - static_cast<int>(j));
        }
    }
    return late;
}

inline constexpr auto kCrcWide = make_wide();
inline constexpr auto kCrcLate = make_late();

}  // namespace detail

// Byte-at-a-time reference implementation, exactly the seed's algorithm.
constexpr std::uint32_t crc32_reference(std::span<const std::uint8_t> data) {
    std::uint32_t reg = kCrcInit;
    for (std::uint8_t byte : data) {
        reg = detail::four_steps(reg ^ byte);
    }
    return reg;
}

// The fast implementation used by the codec; equal to crc32_reference.
constexpr std::uint32_t crc32(std::span<const std::uint8_t> data) {
    const auto& s = detail::kCrcSlices;
    const auto& w = detail::kCrcWide;
    const auto& late = detail::kCrcLate;
    std::uint32_t reg = kCrcInit;
    std::size_t i = 0;
    for (; i + 4 <= data.size(); i += 4) {
        const std::uint32_t r = reg ^ data[i];
        reg = w[0][r & 0xFFU] ^ w[1][(r >> 8) & 0xFFU] ^ w[2][(r >> 16) & 0xFFU] ^ w[3][r >> 24] ^
              late[0][data[i + 1]] ^ late[1][data[i + 2]] ^ late[2][data[i + 3]];
    }
    for (std::uint8_t byte : data.subspan(i)) {
        reg ^= byte;
        reg = s[0][reg & 0xFFU] ^ s[1][(reg >> 8) & 0xFFU] ^ s[2][(reg >> 16) & 0xFFU] ^
              s[3][reg >> 24];
    }
    return reg;
}

}  // namespace gport::protocol
