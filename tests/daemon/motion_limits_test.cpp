// The soft limits on angle and speed commands (MotionLimits).
#include "gport/daemon/core/motion_limits.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace gport::daemon {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::IsEmpty;

config::LimitsConfig limits() {
    config::LimitsConfig c;
    c.pitch = {-90.0, 30.0};
    c.yaw = {-170.5, 170.5};
    c.max_speed = 100.0;
    return c;
}

TEST(MotionLimits, DefaultsAllowTheWholeRange) {
    const MotionLimits none{config::LimitsConfig{}};
    for (std::int16_t v : {-32767, -1, 0, 1, 32767}) {
        const protocol::Axes axes{v, v, v};
        auto angle = none.angle(axes, false);
        ASSERT_TRUE(angle.ok()) << v;
        EXPECT_EQ(angle->axes, axes);
        EXPECT_THAT(angle->clamped, IsEmpty());
        auto speed = none.speed(axes, false);
        ASSERT_TRUE(speed.ok()) << v;
        EXPECT_EQ(speed->axes, axes);
    }
}

TEST(MotionLimits, AnglesWithinTheRangeIncludingItsEndsPass) {
    const MotionLimits m{limits()};
    for (const protocol::Axes a : {protocol::Axes{0, -9000, -17050}, protocol::Axes{0, 3000, 17050},
                                   protocol::Axes{32767, 0, 0}}) {
        auto r = m.angle(a, false);
        ASSERT_TRUE(r.ok()) << r.error().message;
        EXPECT_EQ(r->axes, a);
        EXPECT_THAT(r->clamped, IsEmpty());
    }
}

TEST(MotionLimits, AnAngleOutsideIsRefusedNamingAxisValueAndRange) {
    const MotionLimits m{limits()};
    auto r = m.angle({0, -10000, 0}, false);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::kInvalidParams);
    EXPECT_THAT(r.error().message,
                HasSubstr("pitch = -100 is outside the soft limit -90 to 30 (limits.pitch)"));
    auto yaw = m.angle({0, 0, 17051}, false);
    ASSERT_FALSE(yaw.ok());
    EXPECT_THAT(yaw.error().message, HasSubstr("yaw = 170.51 is outside the soft limit -170.5 to "
                                               "170.5 (limits.yaw)"));
}

TEST(MotionLimits, ClampMovesEachAxisIntoItsRangeAndSaysWhich) {
    const MotionLimits m{limits()};
    auto r = m.angle({1000, -10000, 20000}, true);
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(r->axes, (protocol::Axes{1000, -9000, 17050}));
    EXPECT_THAT(r->clamped, ElementsAre("pitch", "yaw"));
    auto high = m.angle({0, 4500, 0}, true);
    ASSERT_TRUE(high.ok());
    EXPECT_EQ(high->axes.pitch, 3000);
    EXPECT_THAT(high->clamped, ElementsAre("pitch"));
}

TEST(MotionLimits, ASpeedFasterThanTheLimitOnAnyAxisIsRefused) {
    const MotionLimits m{limits()};
    EXPECT_TRUE(m.speed({10000, -10000, 0}, false).ok());
    auto r = m.speed({0, 0, -15000}, false);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::kInvalidParams);
    EXPECT_THAT(r.error().message, HasSubstr("yaw = -150 °/s"));
    EXPECT_THAT(r.error().message, HasSubstr("100 °/s (limits.max_speed)"));
}

TEST(MotionLimits, ClampedSpeedsKeepTheirDirection) {
    const MotionLimits m{limits()};
    auto r = m.speed({20000, 500, -32767}, true);
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(r->axes, (protocol::Axes{10000, 500, -10000}));
    EXPECT_THAT(r->clamped, ElementsAre("roll", "yaw"));
}

}  // namespace
}  // namespace gport::daemon
