// The "failsafe" section: what is sent when a speed motion loses its commander.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace gport::config::test
