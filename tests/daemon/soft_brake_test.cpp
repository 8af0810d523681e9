// SoftBrake, the pure rule behind braking at the soft limits: which axes a
// speed moves towards a narrowed side, and when they are within the braking
// distance |speed| × (age + lookahead) + margin of it.
#include "gport/daemon/core/soft_brake.hpp"

#include <gtest/gtest.h>

namespace gport::daemon {
namespace {

using namespace std::chrono_literals;
using protocol::Axes;

config::LimitsConfig pitch_up_to(double max, double margin = 1.0) {
    config::LimitsConfig c;
    c.pitch.max = max;
    c.braking_margin_deg = margin;
    return c;
}

TEST(SoftBrake, TheDistanceIsSpeedTimesAgePlusLookaheadPlusTheMargin) {
    const SoftBrake brake(pitch_up_to(20, 1.5), 100ms);
    EXPECT_DOUBLE_EQ(brake.distance(30, 0ms), 30 * 0.1 + 1.5);
    EXPECT_DOUBLE_EQ(brake.distance(-30, 50ms), 30 * 0.15 + 1.5) << "either direction";
    EXPECT_DOUBLE_EQ(brake.distance(0, 50ms), 1.5);
}

TEST(SoftBrake, OnlyANarrowedSideInTheDirectionOfMotionNeedsAttitude) {
    const SoftBrake brake(pitch_up_to(20), 100ms);
    EXPECT_EQ(brake.needs_attitude({0, 100, 0}), std::vector<std::string>{"pitch"});
    EXPECT_TRUE(brake.needs_attitude({0, -100, 0}).empty()) << "min is not narrowed";
    EXPECT_TRUE(brake.needs_attitude({100, 0, -100}).empty()) << "roll and yaw are not";
    EXPECT_TRUE(SoftBrake(config::LimitsConfig{}, 100ms).needs_attitude({1, 1, 1}).empty());
}

TEST(SoftBrake, BrakesWithinTheDistanceAndBeyondButNotInwards) {
    const SoftBrake brake(pitch_up_to(20), 100ms);  // 30 °/s: distance 4°
    const auto far = brake.apply({0, 3000, 500}, {0, 1500, 0}, 0ms);
    EXPECT_TRUE(far.braked.empty()) << "5° left";
    EXPECT_EQ(far.speed, (Axes{0, 3000, 500}));
    const auto near = brake.apply({0, 3000, 500}, {0, 1601, 0}, 0ms);
    EXPECT_EQ(near.braked, std::vector<std::string>{"pitch"}) << "3.99° left";
    EXPECT_EQ(near.speed, (Axes{0, 0, 500}));
    EXPECT_EQ(brake.apply({0, 3000, 0}, {0, 1500, 0}, 50ms).braked.size(), 1U)
        << "an older sample: the gimbal has moved on (5.5° distance)";
    EXPECT_EQ(brake.apply({0, 10, 0}, {0, 2500, 0}, 0ms).braked.size(), 1U) << "beyond";
    EXPECT_TRUE(brake.apply({0, -3000, 0}, {0, 2500, 0}, 0ms).braked.empty()) << "inwards";
}

TEST(SoftBrake, MergedKeepsRollPitchYawOrder) {
    EXPECT_EQ(merged({"yaw"}, {"roll", "yaw"}), (std::vector<std::string>{"roll", "yaw"}));
    EXPECT_TRUE(merged({}, {}).empty());
    EXPECT_TRUE(moves({0, 0, 1}));
    EXPECT_FALSE(moves({}));
}

}  // namespace
}  // namespace gport::daemon
