// The "failsafe" section: what is sent when a speed motion loses its commander.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "gport/config/advisories.hpp"
#include "test_support.hpp"

namespace gport::config::test {
namespace {

using ::testing::ElementsAre;

TEST(ConfigFailsafe, DefaultsAreStop) {
    auto c = load("{}");
    ASSERT_TRUE(c.ok());
    EXPECT_EQ(c->failsafe.on_owner_gone, Failsafe::kStop);
    EXPECT_EQ(c->failsafe.on_shutdown, Failsafe::kStop);
    EXPECT_EQ(c->failsafe.on_link_lost, Failsafe::kStop);
}

TEST(ConfigFailsafe, PoliciesAreRead) {
    auto c = load(R"({"failsafe": {"on_owner_gone": "center", "on_shutdown": "hold",
                                   "on_link_lost": "center"}})");
    ASSERT_TRUE(c.ok()) << c.error().text();
    EXPECT_EQ(c->failsafe.on_owner_gone, Failsafe::kCenter);
    EXPECT_EQ(c->failsafe.on_shutdown, Failsafe::kHold);
    EXPECT_EQ(c->failsafe.on_link_lost, Failsafe::kCenter);
    c = load(R"({"failsafe": {"on_owner_gone": "hold", "on_shutdown": "stop"}})");
    ASSERT_TRUE(c.ok()) << c.error().text();
    EXPECT_EQ(c->failsafe.on_owner_gone, Failsafe::kHold);
    EXPECT_EQ(c->failsafe.on_shutdown, Failsafe::kStop);
}

TEST(ConfigFailsafe, ErrorsNameTheKeyAndTheAllowedValues) {
    EXPECT_THAT(errors_of(R"({"failsafe": {"on_owner_gone": "park"}})"),
                ElementsAre(ErrorWith("failsafe.on_owner_gone",
                                      R"("stop", "hold" or "center", got "park")")));
    EXPECT_THAT(
        errors_of(R"({"failsafe": {"on_shutdown": 1}})"),
        ElementsAre(ErrorWith("failsafe.on_shutdown", R"("stop", "hold" or "center")", "got 1")));
    EXPECT_THAT(errors_of(R"({"failsafe": {"on_link_lost": "hold"}})"),
                ElementsAre(ErrorWith("failsafe.on_link_lost", R"(must be "stop" or "center")",
                                      "no recent attitude to hold")));
    EXPECT_THAT(
        errors_of(R"({"failsafe": {"on_link_lost": "Stop"}})"),
        ElementsAre(ErrorWith("failsafe.on_link_lost", R"("stop" or "center", got "Stop")")));
    EXPECT_THAT(errors_of(R"({"failsafe": {"on_owner_lost": "stop"}})"),
                ElementsAre(ErrorWith("on_owner_lost", "on_owner_gone")));
}

// A centre outside the soft limits is accepted (the centre is clamped into
// them, as for the center command) with one warning per axis at start.
TEST(ConfigFailsafe, ACentreOutsideTheLimitsIsAcceptedWithAWarningNamingTheAxis) {
    auto c = load(R"({"failsafe": {"on_owner_gone": "center", "on_link_lost": "center"},
                      "limits": {"pitch": {"min": -60, "max": -10}}})");
    ASSERT_TRUE(c.ok()) << c.error().text();
    EXPECT_THAT(advisories(*c),
                ElementsAre("failsafe.on_owner_gone, failsafe.on_link_lost is \"center\", but 0° "
                            "lies outside limits.pitch (-60 to -10): the failsafe's centre (like "
                            "the center command) aims pitch at -10° instead"));
}

TEST(ConfigFailsafe, NoWarningWithoutACentrePolicyOrWithZeroInside) {
    auto c = load(R"({"limits": {"pitch": {"min": -60, "max": -10}}})");
    ASSERT_TRUE(c.ok());
    EXPECT_TRUE(advisories(*c).empty()) << "the policy is stop";
    c = load(R"({"failsafe": {"on_shutdown": "center"},
                 "limits": {"pitch": {"min": -60, "max": 0}, "yaw": {"min": 0, "max": 90}}})");
    ASSERT_TRUE(c.ok());
    EXPECT_TRUE(advisories(*c).empty()) << "0 is on the edge of both ranges";
}

}  // namespace
}  // namespace gport::config::test
