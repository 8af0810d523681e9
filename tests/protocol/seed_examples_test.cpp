// Every example frame of the G-Port protocol document, byte for byte. Where
// the CRC proves the printed text wrong, the corrected frame is used and the
// erratum is named (docs/protocol.md, "Errata").
#include <gtest/gtest.h>

#include <vector>

#include "gport/protocol/crc32.hpp"
#include "gport/protocol/decoder.hpp"
#include "gport/protocol/messages.hpp"

namespace gp = gport::protocol;

namespace {

using Bytes = std::vector<std::uint8_t>;

Bytes bytes_of(const gp::Frame& f) {
    return {f.bytes().begin(), f.bytes().end()};
}

// Decodes exactly one frame from `wire` and returns its typed message.
gp::Message decode_one(const Bytes& wire) {
    gp::Decoder dec;
    std::vector<gp::Message> out;
    dec.feed(wire, [&](const gp::FrameView& f) {
        auto m = gp::decode(f);
        ASSERT_TRUE(m.ok()) << m.error().message;
        out.push_back(*m);
    });
    EXPECT_EQ(dec.stats().garbage_bytes, 0U);
    EXPECT_EQ(out.size(), 1U);
    return out.empty() ? gp::Message{} : out.front();
}

}  // namespace

TEST(SeedCrcTable, GeneratedTableMatchesEveryCorrectlyPrintedEntry) {
    // The four entries the seed misprints, with the values the polynomial gives.
    EXPECT_EQ(gp::detail::kCrcTable.at(74), 0x1B0CA6A1U);   // printed 0x1BOCA6A1 (letter O)
    EXPECT_EQ(gp::detail::kCrcTable.at(119), 0xFEF34DE2U);  // printed 0xFE34DE2 (digit lost)
    EXPECT_EQ(gp::detail::kCrcTable.at(155), 0x0E56F0FFU);  // printed 0x0E56FOFF (letter O)
    EXPECT_EQ(gp::detail::kCrcTable.at(236), 0xF0A5BD1DU);  // printed 0xFOA5BD1D (letter O)
    // A few correctly printed entries, first, middle and last.
    EXPECT_EQ(gp::detail::kCrcTable.at(0), 0x00000000U);
    EXPECT_EQ(gp::detail::kCrcTable.at(1), 0x04C11DB7U);
    EXPECT_EQ(gp::detail::kCrcTable.at(128), 0x690CE0EEU);
    EXPECT_EQ(gp::detail::kCrcTable.at(255), 0xB1F740B4U);
}

TEST(SeedExamples, GetSettings0x13) {
    const Bytes wire{0xAE, 0x01, 0x00, 0x13, 0x14};
    EXPECT_EQ(bytes_of(gp::encode(gp::GetSettings{})), wire);
    EXPECT_EQ(decode_one(wire), gp::Message{gp::GetSettings{}});
}

TEST(SeedExamples, SettingsReport0x14) {
    const Bytes wire{0xAE, 0x01, 0x0F, 0x14, 0x24, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
                     0x00, 0x00, 0x00, 0x00, 0x32, 0x0A, 0xFF, 0x00, 0x26, 0x37, 0x1B, 0xBA};
    gp::SettingsBlock block;
    block.dead_zone = 50;
    block.follow_speed = 10;
    block.inverted_raw = -1;
    EXPECT_EQ(bytes_of(gp::encode(gp::SettingsReport{block})), wire);
    const auto msg = decode_one(wire);
    ASSERT_TRUE(std::holds_alternative<gp::SettingsReport>(msg));
    EXPECT_TRUE(std::get<gp::SettingsReport>(msg).block.inverted());
}

TEST(SeedExamples, SetSettings0x15CorrectedExtraZeroByte) {
    // Erratum: the printed example carries 16 data bytes (one 00 too many)
    // for len 0x0F; its CRC 26 37 1B BA is that of the 15-byte block below.
    const Bytes wire{0xAE, 0x01, 0x0F, 0x15, 0x25, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
                     0x00, 0x00, 0x00, 0x00, 0x32, 0x0A, 0xFF, 0x00, 0x26, 0x37, 0x1B, 0xBA};
    gp::SettingsBlock block;
    block.dead_zone = 50;
    block.follow_speed = 10;
    block.inverted_raw = -1;
    EXPECT_EQ(bytes_of(gp::encode(gp::SetSettings{block})), wire);
    EXPECT_EQ(decode_one(wire), gp::Message{gp::SetSettings{block}});
}

TEST(SeedExamples, SetSettingsAck0x16) {
    const Bytes wire{0xAE, 0x01, 0x00, 0x16, 0x17};
    EXPECT_EQ(bytes_of(gp::encode(gp::SetSettingsAck{})), wire);
    EXPECT_EQ(decode_one(wire), gp::Message{gp::SetSettingsAck{}});
}

TEST(SeedExamples, SpeedYaw30CorrectedExtraZeroByte) {
    // Erratum: the printed example has 14 data bytes for len 0x0D (one 00 too
    // many); with yaw speed 3000 at bytes 11-12 the CRC is CC F5 E1 63.
    const Bytes wire{0xAE, 0x01, 0x0D, 0x85, 0x93, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00,
                     0x00, 0x00, 0x00, 0x00, 0x00, 0xB8, 0x0B, 0xCC, 0xF5, 0xE1, 0x63};
    const auto cmd = gp::Control::speed_of({0, 0, 3000});
    EXPECT_EQ(bytes_of(gp::encode(cmd)), wire);
    EXPECT_EQ(decode_one(wire), gp::Message{cmd});
}

TEST(SeedExamples, AngleYaw30CorrectedShiftedValue) {
    // Erratum: the printed example puts B8 0B at bytes 6-7 (one byte late);
    // yaw angle is bytes 5-6, and only that layout gives CRC 76 AB AF 70.
    const Bytes wire{0xAE, 0x01, 0x0D, 0x85, 0x93, 0x02, 0x00, 0x00, 0x00, 0x00, 0xB8,
                     0x0B, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x76, 0xAB, 0xAF, 0x70};
    const auto cmd = gp::Control::angle_of({0, 0, 3000});
    EXPECT_EQ(bytes_of(gp::encode(cmd)), wire);
    EXPECT_EQ(decode_one(wire), gp::Message{cmd});
}

TEST(SeedExamples, ReturnToCenter) {
    const Bytes wire{0xAE, 0x01, 0x0D, 0x85, 0x93, 0x03, 0x00, 0x00, 0x00, 0x00, 0x00,
                     0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x44, 0x06, 0xBE, 0x68};
    EXPECT_EQ(bytes_of(gp::encode(gp::Control::center())), wire);
    EXPECT_EQ(decode_one(wire), gp::Message{gp::Control::center()});
}

TEST(SeedExamples, CameraToggleRecording) {
    const Bytes wire{0xAE, 0x01, 0x01, 0x86, 0x88, 0x01, 0xCC, 0xC0, 0xC5, 0xC3};
    const gp::Camera cmd{gp::CameraAction::kToggleRecording};
    EXPECT_EQ(bytes_of(gp::encode(cmd)), wire);
    EXPECT_EQ(decode_one(wire), gp::Message{cmd});
}

TEST(SeedExamples, Attitude0x87) {
    const Bytes wire{0xAE, 0x01, 0x0C, 0x87, 0x94, 0x00, 0x00, 0x00, 0x00, 0xA7, 0xF0,
                     0x7F, 0xF8, 0xF0, 0xFF, 0xD2, 0x01, 0x44, 0x0D, 0xAD, 0x53};
    const gp::Attitude att{{0, 0, -3929}, {-1921, -16, 466}, std::nullopt};
    EXPECT_EQ(bytes_of(gp::encode(att)), wire);
    EXPECT_EQ(decode_one(wire), gp::Message{att});
    EXPECT_DOUBLE_EQ(gp::from_centi(att.imu.yaw), -39.29);
    EXPECT_DOUBLE_EQ(gp::from_centi(att.hall.roll), -19.21);
}
