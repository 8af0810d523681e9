// The "limits" section: soft angle ranges per axis and the speed limit.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "test_support.hpp"

namespace gport::config::test {
namespace {

using ::testing::ElementsAre;

TEST(ConfigLimits, DefaultsAreTheWholeRange) {
    auto c = load("{}");
    ASSERT_TRUE(c.ok());
    for (const auto* range : {&c->limits.roll, &c->limits.pitch, &c->limits.yaw}) {
        EXPECT_EQ(range->min, -327.67);
        EXPECT_EQ(range->max, 327.67);
    }
    EXPECT_EQ(c->limits.max_speed, 327.67);
    EXPECT_EQ(c->limits.braking_margin_deg, 1.0);
}

TEST(ConfigLimits, TheBrakingMarginIsReadAndChecked) {
    auto c = load(R"({"limits": {"braking_margin_deg": 2.5}})");
    ASSERT_TRUE(c.ok()) << c.error().text();
    EXPECT_EQ(c->limits.braking_margin_deg, 2.5);
    EXPECT_EQ(load(R"({"limits": {"braking_margin_deg": 0}})")->limits.braking_margin_deg, 0.0);
    EXPECT_THAT(errors_of(R"({"limits": {"braking_margin_deg": -1}})"),
                ElementsAre(ErrorWith("limits.braking_margin_deg", "from 0 to 90", "got -1")));
    EXPECT_THAT(errors_of(R"({"limits": {"braking_margin_deg": 91}})"),
                ElementsAre(ErrorWith("limits.braking_margin_deg", "got 91")));
    EXPECT_THAT(errors_of(R"({"limits": {"braking_margin_deg": "1"}})"),
                ElementsAre(ErrorWith("limits.braking_margin_deg", "got \"1\"")));
}

TEST(ConfigLimits, ValidLimitsAreRead) {
    auto c = load(R"({"limits": {"pitch": {"min": -90, "max": 30}, "yaw": {"max": 170.5},
                                 "roll": {"min": -327.67, "max": 327.67}, "max_speed": 45.5}})");
    ASSERT_TRUE(c.ok()) << c.error().text();
    EXPECT_EQ(c->limits.pitch.min, -90.0);
    EXPECT_EQ(c->limits.pitch.max, 30.0);
    EXPECT_EQ(c->limits.yaw.min, -327.67);
    EXPECT_EQ(c->limits.yaw.max, 170.5);
    EXPECT_EQ(c->limits.max_speed, 45.5);
}

TEST(ConfigLimits, MinMustBeLessThanMax) {
    EXPECT_THAT(errors_of(R"({"limits": {"pitch": {"min": 30, "max": -90}}})"),
                ElementsAre(ErrorWith("limits.pitch", "min (30) must be less than max (-90)")));
    EXPECT_THAT(errors_of(R"({"limits": {"roll": {"min": 10, "max": 10}}})"),
                ElementsAre(ErrorWith("limits.roll", "min (10) must be less than max (10)")));
    EXPECT_THAT(errors_of(R"({"limits": {"yaw": {"min": 327.67}}})"),
                ElementsAre(ErrorWith("limits.yaw", "max (327.67, the default)")));
}

TEST(ConfigLimits, OutOfRangeValuesNameTheKeyPathAndRange) {
    EXPECT_THAT(errors_of(R"({"limits": {"pitch": {"min": -400}}})"),
                ElementsAre(ErrorWith("limits.pitch.min", "from -327.67 to 327.67", "got -400")));
    EXPECT_THAT(errors_of(R"({"limits": {"yaw": {"max": "90"}}})"),
                ElementsAre(ErrorWith("limits.yaw.max", "got \"90\"")));
    EXPECT_THAT(errors_of(R"({"limits": {"max_speed": 0}})"),
                ElementsAre(ErrorWith("limits.max_speed", "from 0.01 to 327.67", "got 0")));
    EXPECT_THAT(errors_of(R"({"limits": {"max_speed": 400}})"),
                ElementsAre(ErrorWith("limits.max_speed", "got 400")));
    EXPECT_THAT(errors_of(R"({"limits": {"roll": 5}})"),
                ElementsAre(ErrorWith("limits.roll", "must be an object with the keys min, max")));
}

TEST(ConfigLimits, UnknownKeysAreRefused) {
    EXPECT_THAT(errors_of(R"({"limits": {"tilt": {}}})"),
                ElementsAre(ErrorWith("\"limits.tilt\"",
                                      "roll, pitch, yaw, max_speed, braking_margin_deg")));
    EXPECT_THAT(errors_of(R"({"limits": {"pitch": {"low": -90}}})"),
                ElementsAre(ErrorWith("\"limits.pitch.low\"", "limits.pitch: min, max")));
}

}  // namespace
}  // namespace gport::config::test
