// The fast CRC (four independent slice lookups per byte) against the seed's
// byte-at-a-time reference algorithm, and against the CRCs the seed prints.
#include "gport/protocol/crc32.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

namespace gp = gport::protocol;

namespace {

using Bytes = std::vector<std::uint8_t>;

// The wire carries the CRC little-endian; the vectors below are as printed.
std::uint32_t from_le(std::uint8_t b0, std::uint8_t b1, std::uint8_t b2, std::uint8_t b3) {
    return static_cast<std::uint32_t>(b0) | static_cast<std::uint32_t>(b1) << 8 |
           static_cast<std::uint32_t>(b2) << 16 | static_cast<std::uint32_t>(b3) << 24;
}

Bytes zeros_then(std::size_t zeros, std::initializer_list<std::uint8_t> tail) {
    Bytes b(zeros, 0);
    b.insert(b.end(), tail);
    return b;
}

// A control-mode byte followed by the rest of a 0x85 data field. (Sized up
// front: g++ 12 warns falsely about inserting into a one-byte vector.)
Bytes cat_mode(std::uint8_t mode, const Bytes& rest) {
    Bytes b(rest.size() + 1, mode);
    std::copy(rest.begin(), rest.end(), b.begin() + 1);
    return b;
}

}  // namespace

TEST(Crc32, FastEqualsReferenceOnRandomDataOfEveryLength) {
    std::mt19937 rng(20240601);
    std::uniform_int_distribution<int> byte(0, 255);
    for (std::size_t len = 0; len <= 300; ++len) {
        for (int round = 0; round < 4; ++round) {
            Bytes data(len);
            for (auto& b : data) {
                b = static_cast<std::uint8_t>(byte(rng));
            }
            ASSERT_EQ(gp::crc32(data), gp::crc32_reference(data)) << "length " << len;
        }
    }
}

TEST(Crc32, FastEqualsReferenceOnSingleBytesAndExtremes) {
    for (int v = 0; v < 256; ++v) {
        const Bytes one{static_cast<std::uint8_t>(v)};
        ASSERT_EQ(gp::crc32(one), gp::crc32_reference(one)) << "byte " << v;
    }
    const Bytes ones(255, 0xFF);
    EXPECT_EQ(gp::crc32(ones), gp::crc32_reference(ones));
    const Bytes headers(255, 0xAE);
    EXPECT_EQ(gp::crc32(headers), gp::crc32_reference(headers));
}

TEST(Crc32, EmptyDataLeavesTheInitialRegister) {
    EXPECT_EQ(gp::crc32({}), gp::kCrcInit);
    EXPECT_EQ(gp::crc32_reference({}), gp::kCrcInit);
}

TEST(Crc32, UsableAtCompileTime) {
    static constexpr std::uint8_t kCamera[] = {0x01};
    static_assert(gp::crc32(kCamera) == 0xC3C5C0CCU);
    static_assert(gp::crc32_reference(kCamera) == 0xC3C5C0CCU);
    SUCCEED();
}

// Known vectors: the data fields of the seed's examples (corrected where the
// seed misprints them) and the CRC printed after each.
TEST(Crc32, SeedVectors) {
    struct Vector {
        const char* name;
        Bytes data;
        std::uint32_t crc;
    };
    const std::vector<Vector> vectors = {
        {"0x14/0x15 settings", zeros_then(11, {0x32, 0x0A, 0xFF, 0x00}),
         from_le(0x26, 0x37, 0x1B, 0xBA)},
        {"0x85 speed yaw 30", cat_mode(0x01, zeros_then(10, {0xB8, 0x0B})),
         from_le(0xCC, 0xF5, 0xE1, 0x63)},
        {"0x85 angle yaw 30", cat_mode(0x02, zeros_then(4, {0xB8, 0x0B, 0, 0, 0, 0, 0, 0})),
         from_le(0x76, 0xAB, 0xAF, 0x70)},
        {"0x85 centre", cat_mode(0x03, Bytes(12, 0)), from_le(0x44, 0x06, 0xBE, 0x68)},
        {"0x86 record", Bytes{0x01}, from_le(0xCC, 0xC0, 0xC5, 0xC3)},
        {"0x87 attitude",
         Bytes{0x00, 0x00, 0x00, 0x00, 0xA7, 0xF0, 0x7F, 0xF8, 0xF0, 0xFF, 0xD2, 0x01},
         from_le(0x44, 0x0D, 0xAD, 0x53)},
    };
    for (const auto& v : vectors) {
        EXPECT_EQ(gp::crc32(v.data), v.crc) << v.name;
        EXPECT_EQ(gp::crc32_reference(v.data), v.crc) << v.name;
    }
}

// The seed's misprinted examples: their printed CRC does not match their
// printed data, which is how the CRC proves them wrong (docs/protocol.md).
TEST(Crc32, SeedMisprintsDoNotMatchTheirPrintedCrc) {
    const Bytes settings16 = zeros_then(12, {0x32, 0x0A, 0xFF, 0x00});  // 0x15: 16 bytes
    EXPECT_NE(gp::crc32(settings16), from_le(0x26, 0x37, 0x1B, 0xBA));
    const Bytes speed14 = cat_mode(0x01, zeros_then(11, {0xB8, 0x0B}));  // 14 bytes
    EXPECT_NE(gp::crc32(speed14), from_le(0xCC, 0xF5, 0xE1, 0x63));
    // The angle example as printed (B8 0B one byte late) would need D9 24 E4 57.
    const Bytes angle_printed = cat_mode(0x02, zeros_then(5, {0xB8, 0x0B, 0, 0, 0, 0, 0}));
    ASSERT_EQ(angle_printed.size(), 13U);
    EXPECT_EQ(gp::crc32(angle_printed), from_le(0xD9, 0x24, 0xE4, 0x57));
}
