#include "gport/mavlink/messages.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <vector>

#include "samples.hpp"

namespace gm = gport::mavlink;
namespace gt = gport::mavlink::testing;

namespace {

constexpr gm::Header kHeader{17, 42, 154};

TEST(MavlinkMessages, EveryMessageRoundTripsThroughAFrame) {
    for (const gm::Message& m : gt::sample_messages()) {
        const gm::Frame f = gm::encode(m, kHeader);
        const gm::FrameView v = f.view();
        EXPECT_EQ(v.header, kHeader);
        EXPECT_EQ(v.msgid, gm::id_of(m));
        const auto back = gm::decode(v);
        ASSERT_TRUE(back.ok()) << gm::name_of(m) << ": " << back.error().message;
        EXPECT_TRUE(gm::same_bits(*back, m)) << gm::name_of(m);
    }
}

TEST(MavlinkMessages, FieldsLandAtTheirWireOffsets) {
    // GIMBAL_DEVICE_SET_ATTITUDE: q[4] at 0, velocities at 16..27, flags at
    // 28, target_system 30, target_component 31.
    const auto p = gm::payload_of(gt::sample_set_attitude());
    ASSERT_EQ(p.size(), 32U);
    EXPECT_EQ(p[28] | p[29] << 8,
              gm::gimbal_flags::kYawInVehicleFrame | gm::gimbal_flags::kYawLock);
    EXPECT_EQ(p[30], 1);
    EXPECT_EQ(p[31], 154);
    // 0.5235988f little-endian is 0x3F060A92.
    EXPECT_EQ(p[24], 0x92);
    EXPECT_EQ(p[27], 0x3F);
    // COMMAND_LONG: command (uint16) after the seven floats.
    const auto c = gm::payload_of(gt::sample_command_long());
    EXPECT_EQ(c[28] | c[29] << 8, 512);
}

TEST(MavlinkMessages, TrailingZerosAreTruncatedAndZeroExtendedBack) {
    const gm::Frame f = gm::encode(gt::sample_truncated_ack(), kHeader);
    // command 2000 = 0xD0 0x07, result 0 and every extension zero: 2 bytes.
    EXPECT_EQ(f.payload_size(), 2U);
    EXPECT_EQ(f.size(), 14U);
    const auto back = gm::decode(f.view());
    ASSERT_TRUE(back.ok());
    const auto& ack = std::get<gm::CommandAck>(*back);
    EXPECT_EQ(ack.command, 2000);
    EXPECT_EQ(ack.result, 0);
    EXPECT_EQ(ack.progress, 0);
    EXPECT_EQ(ack.result_param2, 0);
}

TEST(MavlinkMessages, AnAllZeroPayloadKeepsItsFirstByte) {
    const gm::Frame f = gm::encode(gm::Heartbeat{.mavlink_version = 0}, kHeader);
    EXPECT_EQ(f.payload_size(), 1U);
    const auto back = gm::decode(f.view());
    ASSERT_TRUE(back.ok());
    EXPECT_EQ(std::get<gm::Heartbeat>(*back).mavlink_version, 0);
}

// Found by mavlink_fuzz: a sender that truncates even the first byte sends
// an empty payload. It decodes as all zeros; our encoder sends the one zero
// byte MAVLink 2 keeps.
TEST(MavlinkMessages, AnEmptyPayloadDecodesAsZerosAndEncodesBackWithItsFirstByte) {
    const gm::FrameView v{kHeader, gm::Heartbeat::kId, {}, false};
    const auto back = gm::decode(v);
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_TRUE(gm::same_bits(*back, gm::Message{gm::Heartbeat{.mavlink_version = 0}}));
    const gm::Frame again = gm::encode(*back, kHeader);
    EXPECT_EQ(again.payload_size(), 1U);
    EXPECT_EQ(again.view().payload[0], 0);
}

TEST(MavlinkMessages, ABasePayloadWithoutExtensionsDecodesWithZeroExtensions) {
    // A sender built before the extensions existed sends the 40 base bytes.
    auto status = gt::sample_attitude_status();
    auto payload = gm::payload_of(status);
    payload.resize(40);
    const gm::FrameView v{kHeader, gm::GimbalDeviceAttitudeStatus::kId, payload, false};
    const auto back = gm::decode(v);
    ASSERT_TRUE(back.ok());
    const auto& s = std::get<gm::GimbalDeviceAttitudeStatus>(*back);
    EXPECT_EQ(s.failure_flags, status.failure_flags);
    EXPECT_EQ(s.delta_yaw, 0.0F);
    EXPECT_EQ(s.gimbal_device_id, 0);
}

TEST(MavlinkMessages, DecodeRefusesUnknownIdsAndOverlongPayloadsByName) {
    const std::vector<std::uint8_t> payload(10, 1);
    const auto unknown = gm::decode({kHeader, 31, payload, false});
    ASSERT_FALSE(unknown.ok());
    EXPECT_NE(unknown.error().message.find("id 31"), std::string::npos);
    const std::vector<std::uint8_t> long_payload(10, 1);
    const auto overlong = gm::decode({kHeader, 0, long_payload, false});
    ASSERT_FALSE(overlong.ok());
    EXPECT_NE(overlong.error().message.find("HEARTBEAT"), std::string::npos);
    EXPECT_NE(overlong.error().message.find("at most 9"), std::string::npos);
}

TEST(MavlinkMessages, StringsAreNulPaddedAndBounded) {
    const auto info = gt::sample_information();
    EXPECT_EQ(gm::text_of(info.vendor_name), "HEQUAV");
    EXPECT_EQ(gm::text_of(info.custom_name), "exactly thirty-two bytes of name");
    const auto too_long = gm::chars_of<32>(std::string(33, 'x'), "custom_name");
    ASSERT_FALSE(too_long.ok());
    EXPECT_NE(too_long.error().message.find("custom_name"), std::string::npos);
    EXPECT_NE(too_long.error().message.find("at most 32"), std::string::npos);
}

TEST(MavlinkMessages, HeaderBytesAndMessageIdAreLaidOutAsSpecified) {
    const gm::Frame f = gm::encode(gt::sample_attitude_status(), {200, 1, 154});
    const auto b = f.bytes();
    EXPECT_EQ(b[0], 0xFD);
    EXPECT_EQ(b[1], f.payload_size());
    EXPECT_EQ(b[2], 0);  // unsigned
    EXPECT_EQ(b[4], 200);
    EXPECT_EQ(b[5], 1);
    EXPECT_EQ(b[6], 154);
    EXPECT_EQ(b[7], 285 & 0xFF);
    EXPECT_EQ(b[8], 285 >> 8);
    EXPECT_EQ(b[9], 0);
}

TEST(MavlinkMessages, FrameMakeRefusesImpossibleInput) {
    const std::vector<std::uint8_t> big(256, 1);
    EXPECT_THROW(gm::Frame::make(kHeader, 0, 50, big), std::invalid_argument);
    EXPECT_THROW(gm::Frame::make(kHeader, 0x1000000, 50, std::vector<std::uint8_t>{1}),
                 std::invalid_argument);
}

}  // namespace
