#include "gport/mavlink/attitude.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace gm = gport::mavlink;

namespace {

constexpr double kTol = 1e-3;  // degrees; floats carry ~1e-5 deg

void expect_angles(const gm::Euler& e, double roll, double pitch, double yaw) {
    EXPECT_NEAR(e.roll, roll, kTol);
    EXPECT_NEAR(e.pitch, pitch, kTol);
    EXPECT_NEAR(e.yaw, yaw, kTol);
}

TEST(MavlinkAttitude, IdentityIsZeroAngles) {
    const auto q = gm::to_quaternion({0, 0, 0});
    EXPECT_FLOAT_EQ(q[0], 1.0F);
    EXPECT_FLOAT_EQ(q[1], 0.0F);
    EXPECT_FLOAT_EQ(q[2], 0.0F);
    EXPECT_FLOAT_EQ(q[3], 0.0F);
    expect_angles(*gm::to_euler(q, "q"), 0, 0, 0);
}

TEST(MavlinkAttitude, SingleAxisQuaternionsHaveTheExpectedComponents) {
    // Yaw 90 right: rotation about z (down) by +90 degrees.
    const auto yaw = gm::to_quaternion({0, 0, 90});
    EXPECT_NEAR(yaw[0], std::sqrt(0.5), 1e-6);
    EXPECT_NEAR(yaw[3], std::sqrt(0.5), 1e-6);
    // Pitch 30 up: about y (right) by +30 degrees.
    const auto pitch = gm::to_quaternion({0, 30, 0});
    EXPECT_NEAR(pitch[0], std::cos(gm::to_radians(15)), 1e-6);
    EXPECT_NEAR(pitch[2], std::sin(gm::to_radians(15)), 1e-6);
    // Roll 10 right: about x (forward).
    const auto roll = gm::to_quaternion({10, 0, 0});
    EXPECT_NEAR(roll[1], std::sin(gm::to_radians(5)), 1e-6);
}

TEST(MavlinkAttitude, RoundTripsOverAGridOfAngles) {
    for (double roll = -170; roll <= 170; roll += 34) {
        for (double pitch = -85; pitch <= 85; pitch += 17) {
            for (double yaw = -175; yaw <= 180; yaw += 35) {
                const auto e = gm::to_euler(gm::to_quaternion({roll, pitch, yaw}), "q");
                ASSERT_TRUE(e.ok());
                expect_angles(*e, roll, pitch, yaw);
            }
        }
    }
}

TEST(MavlinkAttitude, PitchDownThirtyYawFortyFive) {
    // The acceptance case: pitch -30, yaw 45 comes back as such.
    const auto q = gm::to_quaternion({0, -30, 45});
    expect_angles(*gm::to_euler(q, "q"), 0, -30, 45);
}

TEST(MavlinkAttitude, UnnormalisedQuaternionIsNormalisedFirst) {
    auto q = gm::to_quaternion({5, -20, 60});
    for (auto& c : q) {
        c *= 3.0F;
    }
    expect_angles(*gm::to_euler(q, "q"), 5, -20, 60);
}

TEST(MavlinkAttitude, YawWrapsIntoPlusMinus180) {
    expect_angles(*gm::to_euler(gm::to_quaternion({0, 0, 270}), "q"), 0, 0, -90);
    EXPECT_DOUBLE_EQ(gm::wrap_degrees(-180), 180);
    EXPECT_DOUBLE_EQ(gm::wrap_degrees(540), 180);
    EXPECT_DOUBLE_EQ(gm::wrap_degrees(-190), 170);
}

TEST(MavlinkAttitude, GimbalLockPitchStaysFinite) {
    const auto e = gm::to_euler(gm::to_quaternion({0, 90, 0}), "q");
    ASSERT_TRUE(e.ok());
    EXPECT_NEAR(e->pitch, 90, 0.05);
}

TEST(MavlinkAttitude, NaNAndZeroQuaternionsAreRefusedByName) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const gm::Quaternion with_nan{nan, nan, nan, nan};
    EXPECT_TRUE(gm::is_nan(with_nan));
    EXPECT_FALSE(gm::is_nan(gm::to_quaternion({1, 2, 3})));
    const auto e = gm::to_euler(with_nan, "GIMBAL_DEVICE_SET_ATTITUDE.q");
    ASSERT_FALSE(e.ok());
    EXPECT_NE(e.error().message.find("GIMBAL_DEVICE_SET_ATTITUDE.q"), std::string::npos);
    EXPECT_NE(e.error().message.find("NaN"), std::string::npos);
    const auto z = gm::to_euler({0, 0, 0, 0}, "q");
    ASSERT_FALSE(z.ok());
    EXPECT_NE(z.error().message.find("length"), std::string::npos);
}

}  // namespace
