// The gimbal model's laws, stepped on a deterministic clock.
#include "gport/sim/model.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "gport/protocol/decoder.hpp"

namespace gport::sim {
namespace {

namespace p = gport::protocol;
using namespace std::chrono_literals;

std::vector<std::uint8_t> bytes_of(const p::Message& m) {
    const auto f = p::encode(m);
    return {f.bytes().begin(), f.bytes().end()};
}

GimbalModel::Frames send(GimbalModel& model, const p::Message& m) {
    return model.receive(bytes_of(m));
}

p::Message only_message(const GimbalModel::Frames& frames) {
    EXPECT_EQ(frames.size(), 1U);
    auto m = p::decode({frames.at(0).command(), frames.at(0).data()});
    EXPECT_TRUE(m.ok());
    return *m;
}

p::Control speed(double roll, double pitch, double yaw) {
    return p::Control::speed_of(*p::to_axes(roll, pitch, yaw));
}

TEST(ModelMotion, SpeedMovesAtTheCommandedRate) {
    GimbalModel model;
    send(model, speed(0, -10, 30));
    model.advance(500ms);
    EXPECT_NEAR(model.state().hall.yaw, 15.0, 1e-9);
    EXPECT_NEAR(model.state().hall.pitch, -5.0, 1e-9);
    EXPECT_EQ(model.state().hall_rate, (Vec3{0, -10, 30}));
    EXPECT_EQ(model.state().mode, p::ControlMode::kSpeed);
}

TEST(ModelMotion, SpeedStopsOneSecondAfterTheLastCommand) {
    GimbalModel model;
    send(model, speed(0, 0, 30));
    model.advance(999ms);
    EXPECT_TRUE(model.state().speed_active);
    model.advance(2s);
    EXPECT_FALSE(model.state().speed_active);
    EXPECT_NEAR(model.state().hall.yaw, 30.0, 1e-9);
    EXPECT_EQ(model.state().hall_rate, Vec3{});
}

TEST(ModelMotion, RepeatedSpeedCommandsKeepItMoving) {
    GimbalModel model;
    for (int i = 0; i < 20; ++i) {  // 10 Hz for 2 s
        send(model, speed(0, 0, 20));
        model.advance(100ms);
    }
    model.advance(3s);
    // The last command, at 1.9 s, lasts until 2.9 s.
    EXPECT_NEAR(model.state().hall.yaw, 2.9 * 20, 1e-6);
}

TEST(ModelMotion, ZeroSpeedStopsAtOnce) {
    GimbalModel model;
    send(model, speed(0, 0, 30));
    model.advance(200ms);
    send(model, p::Control::stop());
    model.advance(2s);
    EXPECT_NEAR(model.state().hall.yaw, 6.0, 1e-9);
}

TEST(ModelMotion, SpeedStopsAtTheMechanicalLimit) {
    GimbalModel model;
    send(model, speed(-100, 0, 0));
    model.advance(900ms);
    EXPECT_DOUBLE_EQ(model.state().hall.roll, -45.0);
    EXPECT_EQ(model.state().hall_rate.roll, 0.0);
}

TEST(ModelMotion, AngleTargetIsReachedAtTheSlewRate) {
    ModelOptions o;
    o.slew_deg_s = 60;
    GimbalModel model(o);
    send(model, p::Control::angle_of(*p::to_axes(0, -30, 45)));
    model.advance(250ms);
    EXPECT_NEAR(model.state().hall.yaw, 15.0, 1e-9);
    EXPECT_NEAR(model.state().hall.pitch, -15.0, 1e-9);
    EXPECT_EQ(model.state().hall_rate, (Vec3{0, -60, 60}));
    model.advance(250ms);
    EXPECT_NEAR(model.state().hall.pitch, -30.0, 1e-9);  // arrived: holds
    model.advance(500ms);
    EXPECT_EQ(model.state().hall, (Vec3{0, -30, 45}));
    EXPECT_EQ(model.state().hall_rate, Vec3{});
}

TEST(ModelMotion, AngleTargetsAreClampedToTheLimits) {
    GimbalModel model;
    send(model, p::Control::angle_of(*p::to_axes(80, 0, 0)));
    model.advance(5s);
    EXPECT_DOUBLE_EQ(model.state().hall.roll, 45.0);
}

TEST(ModelMotion, CentreReturnsToZeroAtTheSlewRate) {
    GimbalModel model;  // 90 °/s
    send(model, p::Control::angle_of(*p::to_axes(0, 0, 90)));
    model.advance(2s);
    send(model, p::Control::center());
    model.advance(500ms);
    EXPECT_NEAR(model.state().hall.yaw, 45.0, 1e-9);
    model.advance(600ms);
    EXPECT_EQ(model.state().hall, Vec3{});
    EXPECT_EQ(model.state().mode, p::ControlMode::kCenter);
}

TEST(ModelMotion, LockHoldsTheCurrentAttitude) {
    GimbalModel model;
    send(model, speed(0, 0, 40));
    model.advance(250ms);
    send(model, p::Control::lock());
    model.advance(2s);
    EXPECT_NEAR(model.state().hall.yaw, 10.0, 1e-9);
    EXPECT_EQ(model.state().mode, p::ControlMode::kLock);
    EXPECT_FALSE(model.state().speed_active);
}

TEST(ModelMotion, ImuIsHallPlusTheBaseAttitude) {
    ModelOptions o;
    o.base = {1.5, -2.0, 175.0};
    GimbalModel model(o);
    send(model, speed(0, 0, 10));
    model.advance(1s);
    EXPECT_NEAR(model.state().imu.roll, 1.5, 1e-9);
    EXPECT_NEAR(model.state().imu.yaw, -175.0, 1e-9);  // 185 wrapped
}

TEST(ModelSettings, ReadReturnsDistinctiveDefaults) {
    GimbalModel model;
    const auto reply = only_message(send(model, p::GetSettings{}));
    const auto& block = std::get<p::SettingsReport>(reply).block;
    EXPECT_EQ(block, default_settings());
    EXPECT_EQ(block.reserved_head[0], 'G');
    EXPECT_NE(block.reserved_tail, 0);
}

TEST(ModelSettings, WriteIsAcknowledgedAndKeptWholeIncludingReservedBytes) {
    GimbalModel model;
    p::SettingsBlock block = default_settings();
    block.dead_zone = 50;
    block.follow_speed = 0;
    block.set_inverted(true);
    block.reserved_head[3] = 0x77;  // what the client sends is what is kept
    EXPECT_TRUE(std::holds_alternative<p::SetSettingsAck>(
        only_message(send(model, p::SetSettings{block}))));
    const auto reply = only_message(send(model, p::GetSettings{}));
    EXPECT_EQ(std::get<p::SettingsReport>(reply).block, block);
    EXPECT_EQ(model.stats().replies, 2U);
}

TEST(ModelCamera, PhotosAreCountedAndRecordingToggles) {
    GimbalModel model;
    for (int i = 0; i < 3; ++i) {
        EXPECT_TRUE(send(model, p::Camera{p::CameraAction::kPhoto}).empty());
    }
    send(model, p::Camera{p::CameraAction::kToggleRecording});
    EXPECT_EQ(model.state().photos, 3U);
    EXPECT_TRUE(model.state().recording);
    send(model, p::Camera{p::CameraAction::kToggleRecording});
    EXPECT_FALSE(model.state().recording);
}

TEST(ModelStream, EmitsAtTheConfiguredRate) {
    for (double rate : {50.0, 200.0, 7.0}) {
        ModelOptions o;
        o.stream_rate_hz = rate;
        GimbalModel model(o);
        std::size_t frames = 0;
        for (int i = 0; i < 1000; ++i) {  // 10 s in uneven steps
            frames += model.advance(std::chrono::microseconds(7000 + (i % 7) * 1000)).size();
        }
        const double seconds = std::chrono::duration<double>(model.now()).count();
        EXPECT_NEAR(static_cast<double>(frames), rate * seconds, 1.0) << rate;
    }
}

TEST(ModelStream, RateZeroSwitchesTelemetryOff) {
    ModelOptions o;
    o.stream_rate_hz = 0;
    GimbalModel model(o);
    EXPECT_TRUE(model.advance(10s).empty());
    EXPECT_EQ(model.next_emission(), Duration::max());
}

TEST(ModelStream, ShortFormCarriesTwelveBytesOfAttitude) {
    GimbalModel model;
    send(model, speed(0, 0, 30));
    const auto frames = model.advance(500ms);
    ASSERT_EQ(frames.size(), 25U);
    EXPECT_EQ(frames.back().data().size(), p::kAttitudeSize);
    const auto a = std::get<p::Attitude>(only_message({frames.back()}));
    EXPECT_EQ(a.hall.yaw, 1500);  // 0.5 s at 30 °/s, in 0.01°
    EXPECT_EQ(a.imu.yaw, 1500);
    EXPECT_FALSE(a.rates.has_value());
}

TEST(ModelStream, LongFormAddsHallAndImuRates) {
    ModelOptions o;
    o.form = AttitudeForm::kLong24;
    GimbalModel model(o);
    send(model, speed(5, 0, -30));
    const auto frames = model.advance(100ms);
    ASSERT_FALSE(frames.empty());
    EXPECT_EQ(frames.back().data().size(), p::kAttitudeWithRatesSize);
    const auto a = std::get<p::Attitude>(only_message({frames.back()}));
    ASSERT_TRUE(a.rates.has_value());
    EXPECT_EQ(a.rates->hall, (p::Axes{500, 0, -3000}));
    EXPECT_EQ(a.rates->imu_z, -3000);
}

TEST(ModelReceive, BadFramesAreCountedAndIgnored) {
    GimbalModel model;
    std::vector<Received::Kind> seen;
    model.set_listener([&](const Received& r) { seen.push_back(r.kind); });

    auto bad_crc = bytes_of(speed(0, 0, 30));
    bad_crc.back() ^= 0xFF;
    auto bad_header = bytes_of(p::GetSettings{});
    bad_header[4] ^= 0x01;
    // A valid CRC around a control mode the gimbal does not have.
    const std::uint8_t mode9[13] = {9};
    const auto invalid = p::Frame::make(0x85, mode9);
    const auto uplink = bytes_of(p::SetSettingsAck{});

    std::vector<std::uint8_t> stream = {0x00, 0x11};
    for (const auto& part : {bad_crc, bad_header, uplink}) {
        stream.insert(stream.end(), part.begin(), part.end());
    }
    stream.insert(stream.end(), invalid.bytes().begin(), invalid.bytes().end());
    const auto good = bytes_of(p::GetSettings{});
    stream.insert(stream.end(), good.begin(), good.end());

    // One byte at a time, as a slow UART delivers it.
    GimbalModel::Frames replies;
    for (auto b : stream) {
        auto r = model.receive(std::span<const std::uint8_t>(&b, 1));
        replies.insert(replies.end(), r.begin(), r.end());
    }
    EXPECT_EQ(replies.size(), 1U);  // only the good 0x13 is answered
    EXPECT_EQ(model.stats().crc_errors, 1U);
    EXPECT_EQ(model.stats().header_errors, 1U);
    EXPECT_EQ(model.stats().invalid_frames, 1U);
    EXPECT_EQ(model.stats().unexpected_frames, 1U);
    EXPECT_GT(model.stats().garbage_bytes, 2U);
    EXPECT_EQ(model.state().mode, p::ControlMode::kLock);  // nothing bad was obeyed
    EXPECT_NE(std::find(seen.begin(), seen.end(), Received::Kind::kCrcError), seen.end());
    EXPECT_NE(std::find(seen.begin(), seen.end(), Received::Kind::kInvalid), seen.end());
    EXPECT_EQ(seen.back(), Received::Kind::kFrame);
}

TEST(ModelOptionsCheck, RefusesValuesOutsideTheirRange) {
    ModelOptions o;
    o.stream_rate_hz = -1;
    EXPECT_TRUE(validate(o).has_value());
    EXPECT_THROW(GimbalModel{o}, std::invalid_argument);
    o = {};
    o.slew_deg_s = 0;
    EXPECT_NE(validate(o)->find("slew"), std::string::npos);
    o = {};
    o.limits.yaw = 200;
    EXPECT_TRUE(validate(o).has_value());
    EXPECT_FALSE(validate(ModelOptions{}).has_value());
}

}  // namespace
}  // namespace gport::sim
