// The "motion" section: when a tracked angle or centre motion counts as
// reached, and how long it may take.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "test_support.hpp"

namespace gport::config::test {
namespace {

using ::testing::ElementsAre;

TEST(ConfigMotion, DefaultsAreHalfADegreeAndTenSeconds) {
    auto c = load("{}");
    ASSERT_TRUE(c.ok());
    EXPECT_EQ(c->motion.tolerance_deg, 0.5);
    EXPECT_EQ(c->motion.timeout, Millis(10000));
}

TEST(ConfigMotion, ValuesAreRead) {
    auto c = load(R"({"motion": {"tolerance_deg": 1.25, "timeout_ms": 2500}})");
    ASSERT_TRUE(c.ok()) << c.error().text();
    EXPECT_EQ(c->motion.tolerance_deg, 1.25);
    EXPECT_EQ(c->motion.timeout, Millis(2500));
}

TEST(ConfigMotion, ErrorsNameTheKeyAndTheRange) {
    EXPECT_THAT(errors_of(R"({"motion": {"tolerance_deg": 0}})"),
                ElementsAre(ErrorWith("motion.tolerance_deg", "from 0.01 to 10", "got 0")));
    EXPECT_THAT(errors_of(R"({"motion": {"tolerance_deg": "0.5"}})"),
                ElementsAre(ErrorWith("motion.tolerance_deg", "from 0.01 to 10")));
    EXPECT_THAT(errors_of(R"({"motion": {"timeout_ms": 50}})"),
                ElementsAre(ErrorWith("motion.timeout_ms", "100", "600000", "got 50")));
    EXPECT_THAT(errors_of(R"({"motion": {"timeout": 5000}})"),
                ElementsAre(ErrorWith("motion.timeout", "tolerance_deg", "timeout_ms")));
}

}  // namespace
}  // namespace gport::config::test
