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

}  // namespace detail

// The printed-table entry i (exposed so tests can check the generated table).
constexpr std::uint32_t crc_table_entry(std::size_t i) {
    return detail::kCrcTable.at(i);
}

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
    std::uint32_t reg = kCrcInit;
    for (std::uint8_t byte : data) {
        reg ^= byte;
        reg = s[0][reg & 0xFFU] ^ s[1][(reg >> 8) & 0xFFU] ^ s[2][(reg >> 16) & 0xFFU] ^
              s[3][reg >> 24];
    }
    return reg;
}

}  // namespace gport::protocol
