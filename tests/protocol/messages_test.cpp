// Typed messages: encode -> decode round trips, the errors a known command
// with impossible content gives, and the unit conversions.
#include "gport/protocol/messages.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace gp = gport::protocol;
using ::testing::HasSubstr;

namespace {

using Bytes = std::vector<std::uint8_t>;

gp::Result<gp::Message> decode_frame(const gp::Frame& f) {
    return gp::decode(gp::FrameView{f.command(), f.data()});
}

gp::Result<gp::Message> decode_raw(std::uint8_t cmd, const Bytes& data) {
    return gp::decode(gp::FrameView{cmd, data});
}

// encode -> decode must give the message back, and re-encoding it the same frame.
void expect_round_trip(const gp::Message& m) {
    const gp::Frame f = gp::encode(m);
    const auto back = decode_frame(f);
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(*back, m);
    EXPECT_EQ(gp::encode(*back), f);
}

std::string error_of(const gp::Result<gp::Message>& r) {
    EXPECT_FALSE(r.ok());
    return r.ok() ? std::string{} : r.error().message;
}

gp::SettingsBlock sample_block() {
    gp::SettingsBlock b;
    for (std::size_t i = 0; i < b.reserved_head.size(); ++i) {
        b.reserved_head[i] = static_cast<std::uint8_t>(0xA0 + i);  // reserved, kept as is
    }
    b.dead_zone = 200;
    b.follow_speed = 0;
    b.set_inverted(false);
    b.reserved_tail = 0x5A;
    return b;
}

}  // namespace

TEST(MessagesRoundTrip, EveryTypedMessage) {
    expect_round_trip(gp::GetSettings{});
    expect_round_trip(gp::SetSettingsAck{});
    expect_round_trip(gp::SettingsReport{sample_block()});
    expect_round_trip(gp::SetSettings{sample_block()});
    expect_round_trip(gp::Control::speed_of({-32767, 32767, 1}));
    expect_round_trip(gp::Control::stop());
    expect_round_trip(gp::Control::angle_of({100, -9000, 18000}));
    expect_round_trip(gp::Control::center());
    expect_round_trip(gp::Control::lock());
    expect_round_trip(gp::Control{gp::ControlMode::kAngle, {1, 2, 3}, {4, 5, 6}});
    expect_round_trip(gp::Camera{gp::CameraAction::kToggleRecording});
    expect_round_trip(gp::Camera{gp::CameraAction::kPhoto});
    expect_round_trip(gp::RawFrame{0x99, {1, 2, 3}});
    expect_round_trip(gp::RawFrame{0x00, {}});
}

TEST(MessagesRoundTrip, AttitudeTwelveAndTwentyFourByteForms) {
    const gp::Attitude plain{{1, -2, 3}, {-4, 5, -6}, std::nullopt};
    EXPECT_EQ(gp::encode(plain).data().size(), gp::kAttitudeSize);
    expect_round_trip(plain);

    const gp::Attitude with_rates{
        {1, -2, 3}, {-4, 5, -6}, gp::AttitudeRates{{700, -800, 900}, -1000, 1100, -32767}};
    EXPECT_EQ(gp::encode(with_rates).data().size(), gp::kAttitudeWithRatesSize);
    expect_round_trip(with_rates);
}

TEST(MessagesRoundTrip, SettingsReservedBytesAndInversionKept) {
    gp::SettingsBlock b = sample_block();
    b.inverted_raw = -1;
    const auto back = decode_frame(gp::encode(gp::SettingsReport{b}));
    ASSERT_TRUE(back.ok());
    const auto& got = std::get<gp::SettingsReport>(*back).block;
    EXPECT_EQ(got.reserved_head, b.reserved_head);
    EXPECT_EQ(got.reserved_tail, 0x5A);
    EXPECT_TRUE(got.inverted());
    // A value the seed does not define (neither -1 nor 1) survives unchanged.
    b.inverted_raw = 7;
    const auto odd = decode_frame(gp::encode(gp::SetSettings{b}));
    ASSERT_TRUE(odd.ok());
    EXPECT_EQ(std::get<gp::SetSettings>(*odd).block.inverted_raw, 7);
}

TEST(MessagesDecode, LongerAttitudeDecodesItsKnownPrefix) {
    const gp::Attitude with_rates{
        {10, 20, 30}, {40, 50, 60}, gp::AttitudeRates{{70, 80, 90}, 100, 110, 120}};
    const gp::Frame f24 = gp::encode(with_rates);
    Bytes data(f24.data().begin(), f24.data().end());
    data.insert(data.end(), {0xDE, 0xAD, 0xBE, 0xEF, 0x00, 0x01});  // 30 bytes
    const auto r30 = decode_raw(0x87, data);
    ASSERT_TRUE(r30.ok()) << r30.error().message;
    EXPECT_EQ(*r30, gp::Message{with_rates});

    // Between the two forms: the 12-byte prefix, no rates.
    data.resize(18);
    const auto r18 = decode_raw(0x87, data);
    ASSERT_TRUE(r18.ok()) << r18.error().message;
    const gp::Attitude prefix_only{{10, 20, 30}, {40, 50, 60}, std::nullopt};
    EXPECT_EQ(*r18, gp::Message(prefix_only));
}

TEST(MessagesDecode, UnknownCommandIsRawFrameNotError) {
    const Bytes data{0xAE, 0x01, 0x02};
    const auto r = decode_raw(0x42, data);
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(*r, gp::Message(gp::RawFrame{0x42, data}));
}

TEST(MessagesDecode, WrongLengthNamesCommandAndAllowedLength) {
    struct Wrong {
        std::uint8_t cmd;
        std::size_t len;
        const char* allowed;
    };
    for (const Wrong& w : {Wrong{0x13, 1, "0 are allowed"}, Wrong{0x16, 4, "0 are allowed"},
                           Wrong{0x14, 14, "15 are allowed"}, Wrong{0x15, 16, "15 are allowed"},
                           Wrong{0x85, 12, "13 are allowed"}, Wrong{0x85, 14, "13 are allowed"},
                           Wrong{0x86, 0, "1 is allowed"}, Wrong{0x86, 2, "1 is allowed"},
                           Wrong{0x87, 11, "12 or more"}, Wrong{0x87, 0, "12 or more"}}) {
        const std::string msg = error_of(decode_raw(w.cmd, Bytes(w.len, 0x01)));
        char cmd_hex[8];
        std::snprintf(cmd_hex, sizeof cmd_hex, "0x%02X", w.cmd);
        EXPECT_THAT(msg, HasSubstr(cmd_hex));
        EXPECT_THAT(msg, HasSubstr(std::to_string(w.len) + " data bytes"));
        EXPECT_THAT(msg, HasSubstr(w.allowed));
    }
}

TEST(MessagesDecode, BadControlModeIsRefused) {
    for (std::uint8_t mode : {0x00, 0x05, 0xFF, 0x80}) {
        Bytes data(gp::kControlSize, 0);
        data[0] = mode;
        const std::string msg = error_of(decode_raw(0x85, data));
        EXPECT_THAT(msg, HasSubstr("0x85"));
        EXPECT_THAT(msg, HasSubstr(std::to_string(static_cast<std::int8_t>(mode))));
        EXPECT_THAT(msg, HasSubstr("1 speed, 2 angle, 3 centre, 4 lock"));
    }
}

TEST(MessagesDecode, BadCameraActionIsRefused) {
    for (std::uint8_t action : {0x00, 0x03, 0xFF}) {
        const std::string msg = error_of(decode_raw(0x86, Bytes{action}));
        EXPECT_THAT(msg, HasSubstr("0x86"));
        EXPECT_THAT(msg, HasSubstr(std::to_string(static_cast<std::int8_t>(action))));
        EXPECT_THAT(msg, HasSubstr("1 toggle recording, 2 photo"));
    }
}

TEST(MessagesEncode, EncodeOfVariantMatchesEncodeOfAlternative) {
    const gp::Control c = gp::Control::angle_of({1, 2, 3});
    EXPECT_EQ(gp::encode(gp::Message{c}), gp::encode(c));
    // A RawFrame of a known command encodes to that command's frame.
    EXPECT_EQ(gp::encode(gp::RawFrame{0x13, {}}), gp::encode(gp::GetSettings{}));
}

TEST(Frame, MakeRefusesMoreThan255DataBytes) {
    const Bytes too_long(256, 0);
    EXPECT_THROW((void)gp::Frame::make(0x42, too_long), std::length_error);
    const Bytes longest(255, 0);
    const gp::Frame f = gp::Frame::make(0x42, longest);
    EXPECT_EQ(f.size(), gp::kMaxFrameSize);
    EXPECT_EQ(f.data().size(), 255U);
}

TEST(Frame, ZeroLengthFrameHasNoCrc) {
    const gp::Frame f = gp::Frame::make(0x13, {});
    EXPECT_EQ(f.size(), gp::kHeaderSize);
    EXPECT_EQ(Bytes(f.bytes().begin(), f.bytes().end()), (Bytes{0xAE, 0x01, 0x00, 0x13, 0x14}));
}

TEST(Units, ClampedCentiRoundsAsToCentiAndClampsWhatDoesNotFit) {
    EXPECT_EQ(gp::clamped_centi(1.236), 124);
    EXPECT_EQ(gp::clamped_centi(-0.125), -13) << "an exact half: away from zero";
    EXPECT_EQ(gp::clamped_centi(0.005), 1);
    EXPECT_EQ(gp::clamped_centi(327.67), 32767);
    EXPECT_EQ(gp::clamped_centi(1e9), 32767);
    EXPECT_EQ(gp::clamped_centi(-1e9), -32767);
    EXPECT_EQ(gp::clamped_centi(INFINITY), 32767);
    EXPECT_EQ(gp::clamped_centi(NAN), 0);
    for (const double d : {30.0, -89.99, 0.01, 180.0}) {
        EXPECT_EQ(gp::clamped_centi(d), *gp::to_centi(d, "x")) << d;
    }
}

TEST(Units, ToCentiRoundsToNearestStep) {
    EXPECT_EQ(*gp::to_centi(30.0, "yaw"), 3000);
    EXPECT_EQ(*gp::to_centi(1.234, "yaw"), 123);
    EXPECT_EQ(*gp::to_centi(1.236, "yaw"), 124);
    EXPECT_EQ(*gp::to_centi(-1.236, "yaw"), -124);
    EXPECT_EQ(*gp::to_centi(0.125, "yaw"), 13);  // exact half: away from zero
    EXPECT_EQ(*gp::to_centi(-0.125, "yaw"), -13);
    EXPECT_EQ(*gp::to_centi(0.004, "yaw"), 0);
    EXPECT_EQ(*gp::to_centi(-0.0, "yaw"), 0);
    EXPECT_DOUBLE_EQ(gp::from_centi(-3929), -39.29);
}

TEST(Units, LimitsAreSymmetricPlusMinus327_67) {
    EXPECT_EQ(*gp::to_centi(327.67, "pitch"), 32767);
    EXPECT_EQ(*gp::to_centi(-327.67, "pitch"), -32767);
    for (double bad : {327.68, -327.68, 1000.0, -1e9}) {
        const auto r = gp::to_centi(bad, "pitch");
        ASSERT_FALSE(r.ok()) << bad;
        EXPECT_THAT(r.error().message, HasSubstr("pitch"));
        EXPECT_THAT(r.error().message, HasSubstr("-327.67 to 327.67"));
    }
}

TEST(Units, NonFiniteValuesAreRefused) {
    for (double bad :
         {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
          -std::numeric_limits<double>::infinity()}) {
        const auto r = gp::to_centi(bad, "roll speed");
        ASSERT_FALSE(r.ok()) << bad;
        EXPECT_THAT(r.error().message, HasSubstr("roll speed"));
        EXPECT_THAT(r.error().message, HasSubstr("-327.67 to 327.67"));
    }
}

TEST(Units, ToAxesNamesTheFieldThatDoesNotFit) {
    const auto ok = gp::to_axes(1.5, -2.25, 327.67);
    ASSERT_TRUE(ok.ok());
    EXPECT_EQ(*ok, (gp::Axes{150, -225, 32767}));
    EXPECT_THAT(gp::to_axes(400, 0, 0).error().message, HasSubstr("roll"));
    EXPECT_THAT(gp::to_axes(0, -400, 0).error().message, HasSubstr("pitch"));
    EXPECT_THAT(gp::to_axes(0, 0, std::nan("")).error().message, HasSubstr("yaw"));
}
