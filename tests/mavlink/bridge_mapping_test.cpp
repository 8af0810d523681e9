// gport-mavlink's mapping (docs/mavlink.md, "What is mapped"): set-attitude
// to gportd commands, the change filter, sysid adoption, status flags and
// the attitude status.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "gport/mavlink/attitude.hpp"
#include "gport/mavlink/bridge/mapping.hpp"
#include "gport/mavlink/enums.hpp"
#include "gport/mavlink/messages.hpp"

namespace gport::mavlink::bridge {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

GimbalDeviceSetAttitude attitude_of(double roll, double pitch, double yaw,
                                    std::uint16_t flags = gimbal_flags::kYawInVehicleFrame) {
    GimbalDeviceSetAttitude m;
    m.q = to_quaternion({roll, pitch, yaw});
    m.angular_velocity_x = m.angular_velocity_y = m.angular_velocity_z = kNaN;
    m.flags = flags;
    return m;
}

GimbalDeviceSetAttitude rates_of(float x, float y, float z) {
    GimbalDeviceSetAttitude m;
    m.q = {kNaN, kNaN, kNaN, kNaN};
    m.angular_velocity_x = x;
    m.angular_velocity_y = y;
    m.angular_velocity_z = z;
    return m;
}

TEST(SetAttitude, AQuaternionBecomesAnAngleInDegrees) {
    const auto command = map_set_attitude(attitude_of(0, -30, 45), {}, std::nullopt);
    const auto* angle = std::get_if<AngleCommand>(&command);
    ASSERT_NE(angle, nullptr);
    EXPECT_NEAR(angle->target.roll, 0, 1e-3);
    EXPECT_NEAR(angle->target.pitch, -30, 1e-3);
    EXPECT_NEAR(angle->target.yaw, 45, 1e-3);
}

TEST(SetAttitude, InvertFlipsOneAxis) {
    const auto command = map_set_attitude(attitude_of(5, -30, 45), {false, false, true}, {});
    const auto& angle = std::get<AngleCommand>(command);
    EXPECT_NEAR(angle.target.roll, 5, 1e-3);
    EXPECT_NEAR(angle.target.pitch, -30, 1e-3);
    EXPECT_NEAR(angle.target.yaw, -45, 1e-3);
}

TEST(SetAttitude, EarthFrameYawNeedsTheVehicleYaw) {
    const auto earth = attitude_of(0, 0, 100, gimbal_flags::kYawInEarthFrame);
    const auto refused = map_set_attitude(earth, {}, std::nullopt);
    ASSERT_TRUE(std::holds_alternative<NoCommand>(refused));
    EXPECT_NE(std::get<NoCommand>(refused).reason.find("AUTOPILOT_STATE_FOR_GIMBAL_DEVICE"),
              std::string::npos);
    const auto command = map_set_attitude(earth, {}, 30.0);
    EXPECT_NEAR(std::get<AngleCommand>(command).target.yaw, 70, 1e-3);
}

TEST(SetAttitude, YawLockWithoutAFrameFlagIsEarthFrame) {
    EXPECT_TRUE(yaw_in_earth_frame(gimbal_flags::kYawLock));
    EXPECT_FALSE(yaw_in_earth_frame(gimbal_flags::kYawLock | gimbal_flags::kYawInVehicleFrame));
    EXPECT_FALSE(yaw_in_earth_frame(0));
}

TEST(SetAttitude, NaNQuaternionWithRatesIsASpeedInDegreesPerSecond) {
    const auto command =
        map_set_attitude(rates_of(kNaN, 0, static_cast<float>(to_radians(30))), {}, {});
    const auto* speed = std::get_if<SpeedCommand>(&command);
    ASSERT_NE(speed, nullptr);
    EXPECT_EQ(speed->speed.roll, 0);  // NaN axis: 0
    EXPECT_EQ(speed->speed.pitch, 0);
    EXPECT_NEAR(speed->speed.yaw, 30, 1e-4);
}

TEST(SetAttitude, AllNaNIsTheIdleStream) {
    EXPECT_TRUE(
        std::holds_alternative<IdleCommand>(map_set_attitude(rates_of(kNaN, kNaN, kNaN), {}, {})));
}

// PX4's DO_GIMBAL_MANAGER_PITCHYAW with NaN angles and rates 10°/s pitch,
// -20°/s yaw, as its gimbal manager sends it on (issue 31).
GimbalDeviceSetAttitude px4_rates(float pitch_rad_s, float yaw_rad_s) {
    GimbalDeviceSetAttitude m = rates_of(kNaN, pitch_rad_s, yaw_rad_s);
    m.q = {1.0F, 0.0F, 0.0F, 0.0F};
    m.flags = gimbal_flags::kRollLock | gimbal_flags::kPitchLock | gimbal_flags::kYawInVehicleFrame;
    return m;
}

TEST(SetAttitude, RatesWinOverTheNullRotation) {
    const auto message =
        px4_rates(static_cast<float>(to_radians(10)), static_cast<float>(to_radians(-20)));
    EXPECT_TRUE(rates_win(message));
    const auto command = map_set_attitude(message, {}, std::nullopt);
    const auto* speed = std::get_if<SpeedCommand>(&command);
    ASSERT_NE(speed, nullptr);
    EXPECT_NEAR(speed->speed.roll, 0, 1e-9);
    EXPECT_NEAR(speed->speed.pitch, 10, 1e-4);
    EXPECT_NEAR(speed->speed.yaw, -20, 1e-4);
}

TEST(SetAttitude, ZeroRatesWithTheNullRotationStop) {
    const auto command = map_set_attitude(px4_rates(0, 0), {}, std::nullopt);
    const auto* speed = std::get_if<SpeedCommand>(&command);
    ASSERT_NE(speed, nullptr);
    EXPECT_EQ(speed->speed.pitch, 0);
    EXPECT_EQ(speed->speed.yaw, 0);
}

TEST(SetAttitude, TheNullRotationWithoutRatesIsAnAngle) {
    auto message = px4_rates(kNaN, kNaN);
    EXPECT_FALSE(rates_win(message));
    EXPECT_TRUE(std::holds_alternative<AngleCommand>(map_set_attitude(message, {}, {})));
    message.q = to_quaternion({0, -30, 0});  // another angle with rates: the angle
    message.angular_velocity_y = 0.1F;
    EXPECT_FALSE(rates_win(message));
    EXPECT_TRUE(std::holds_alternative<AngleCommand>(map_set_attitude(message, {}, {})));
}

TEST(SetAttitude, NeutralAndRetractCentre) {
    EXPECT_TRUE(std::holds_alternative<CenterCommand>(
        map_set_attitude(attitude_of(0, -30, 45, gimbal_flags::kNeutral), {}, {})));
    auto retract = rates_of(kNaN, kNaN, kNaN);
    retract.flags = gimbal_flags::kRetract;
    EXPECT_TRUE(std::holds_alternative<CenterCommand>(map_set_attitude(retract, {}, {})));
}

TEST(SetAttitude, AZeroQuaternionIsRefusedWithAReason) {
    GimbalDeviceSetAttitude m = attitude_of(0, 0, 0);
    m.q = {0, 0, 0, 0};
    const auto command = map_set_attitude(m, {}, {});
    ASSERT_TRUE(std::holds_alternative<NoCommand>(command));
    EXPECT_FALSE(std::get<NoCommand>(command).reason.empty());
}

TEST(AngleFilter, PassesOnlyMovesAboveTheResolution) {
    AngleFilter filter;
    EXPECT_TRUE(filter.pass({0, -30, 45}));
    EXPECT_FALSE(filter.pass({0, -30, 45}));
    EXPECT_FALSE(filter.pass({0, -30.005, 45.009}));
    EXPECT_TRUE(filter.pass({0, -30, 45.02}));
    filter.reset();
    EXPECT_TRUE(filter.pass({0, -30, 45.02}));
}

TEST(AngleFilter, AStreamedQuaternionPassesOnce) {
    AngleFilter filter;
    int passed = 0;
    for (int i = 0; i < 50; ++i) {
        const auto command = map_set_attitude(attitude_of(0, -30, 45), {}, {});
        passed += filter.pass(std::get<AngleCommand>(command).target) ? 1 : 0;
    }
    EXPECT_EQ(passed, 1);
}

TEST(Addressing, OursOrBroadcast) {
    EXPECT_TRUE(addressed_to(1, 154, 1, 154));
    EXPECT_TRUE(addressed_to(0, 0, 1, 154));
    EXPECT_TRUE(addressed_to(1, 0, 1, 154));
    EXPECT_FALSE(addressed_to(2, 154, 1, 154));
    EXPECT_FALSE(addressed_to(1, 100, 1, 154));
}

TEST(Status, ActiveOnlyWithGportdAndAnUpLink) {
    EXPECT_EQ(system_status({true, "up", true}), mav_state::kActive);
    EXPECT_EQ(system_status({true, "stale", true}), mav_state::kCritical);
    EXPECT_EQ(system_status({true, "down", true}), mav_state::kCritical);
    EXPECT_EQ(system_status({false, "", true}), mav_state::kCritical);
}

TEST(Status, FailureFlags) {
    EXPECT_EQ(failure_flags({true, "up", true}), 0U);
    EXPECT_EQ(failure_flags({true, "stale", true}), gimbal_error::kCommsError);
    EXPECT_EQ(failure_flags({true, "down", true}), gimbal_error::kCommsError);
    EXPECT_EQ(failure_flags({false, "", true}),
              gimbal_error::kCommsError | gimbal_error::kSoftwareError);
    EXPECT_EQ(failure_flags({true, "up", false}), gimbal_error::kNoManager);
}

TEST(AttitudeStatus, QuaternionFromImuRollPitchAndHallYaw) {
    AttitudeInputs in;
    client::AttitudeSample s;
    s.imu = {2, -30, 170};  // IMU yaw is ignored
    s.hall = {1, -29, 45};
    in.sample = s;
    const auto status = make_attitude_status(in, {true, "up", true}, {});
    const auto euler = to_euler(status.q, "q");
    ASSERT_TRUE(euler);
    EXPECT_NEAR(euler->roll, 2, 1e-3);
    EXPECT_NEAR(euler->pitch, -30, 1e-3);
    EXPECT_NEAR(euler->yaw, 45, 1e-3);
    EXPECT_TRUE(status.flags & gimbal_flags::kYawInVehicleFrame);
    EXPECT_TRUE(std::isnan(status.angular_velocity_x));
    EXPECT_TRUE(std::isnan(status.delta_yaw));
    EXPECT_EQ(status.failure_flags, 0U);
}

TEST(AttitudeStatus, RatesAndDeltaYaw) {
    AttitudeInputs in;
    client::AttitudeSample s;
    s.rates = client::Rates{{0, 0, 30}, {10, -20, 99}};
    in.sample = s;
    in.vehicle_yaw_deg = 90;
    const auto status = make_attitude_status(in, {true, "up", true}, {});
    EXPECT_NEAR(status.angular_velocity_x, to_radians(10), 1e-5);
    EXPECT_NEAR(status.angular_velocity_y, to_radians(-20), 1e-5);
    EXPECT_NEAR(status.angular_velocity_z, to_radians(30), 1e-5);
    EXPECT_NEAR(status.delta_yaw, to_radians(90), 1e-5);
    EXPECT_TRUE(std::isnan(status.delta_yaw_velocity));
}

TEST(AttitudeStatus, NoSampleIsNaNWithFailureFlags) {
    const auto status = make_attitude_status({}, {false, "", true}, {});
    EXPECT_TRUE(is_nan(status.q));
    EXPECT_EQ(status.failure_flags, gimbal_error::kCommsError | gimbal_error::kSoftwareError);
}

TEST(Information, SoftLimitsInRadiansElseTheGportsRange) {
    const auto plain = make_information(0, std::nullopt, {});
    EXPECT_NEAR(plain.yaw_min, to_radians(-170), 1e-6) << "before gportd answered";
    EXPECT_NEAR(plain.yaw_max, to_radians(170), 1e-6);
    EXPECT_NEAR(plain.pitch_min, to_radians(-90), 1e-6);
    client::Limits limits;
    limits.roll = {-327.67, 327.67};
    limits.pitch = {-90, 30};
    limits.yaw = {-170, 100};
    const auto info = make_information(0, limits, {false, false, true});
    EXPECT_NEAR(info.roll_min, to_radians(-45), 1e-6) << "no soft limit: the G-Port's range";
    EXPECT_NEAR(info.roll_max, to_radians(45), 1e-6);
    EXPECT_NEAR(info.pitch_min, to_radians(-90), 1e-6);
    EXPECT_NEAR(info.pitch_max, to_radians(30), 1e-6);
    EXPECT_NEAR(info.yaw_min, to_radians(-100), 1e-6) << "inverted: -max";
    EXPECT_NEAR(info.yaw_max, to_radians(170), 1e-6);
}

TEST(Information, VendorModelAndCapabilities) {
    const auto info = make_information(5, std::nullopt, {});
    EXPECT_EQ(text_of(info.vendor_name), "HEQUAV");
    EXPECT_EQ(text_of(info.model_name), "G-Port");
    EXPECT_TRUE(info.cap_flags & gimbal_cap::kHasNeutral);
    EXPECT_TRUE(info.cap_flags & gimbal_cap::kHasYawAxis);
    EXPECT_EQ(info.time_boot_ms, 5U);
}

}  // namespace
}  // namespace gport::mavlink::bridge
