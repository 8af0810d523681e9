// The "motion" section: when a tracked angle or centre motion counts as
// reached, and how long it may take.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "test_support.hpp"

namespace gport::config::test {
namespace {

using ::testing::ElementsAre;

TEST(ConfigMotion, DefaultsAreHalfADegreeTenSecondsAndATwoSecondStall) {
    auto c = load("{}");
    ASSERT_TRUE(c.ok());
    EXPECT_EQ(c->motion.tolerance_deg, 0.5);
    EXPECT_EQ(c->motion.timeout, Millis(10000));
    EXPECT_EQ(c->motion.stall, Millis(2000));
}

TEST(ConfigMotion, ValuesAreRead) {
    auto c = load(R"({"motion": {"tolerance_deg": 1.25, "timeout_ms": 2500, "stall_ms": 750}})");
    ASSERT_TRUE(c.ok()) << c.error().text();
    EXPECT_EQ(c->motion.tolerance_deg, 1.25);
    EXPECT_EQ(c->motion.timeout, Millis(2500));
    EXPECT_EQ(c->motion.stall, Millis(750));
    auto off = load(R"({"motion": {"stall_ms": 0}})");
    ASSERT_TRUE(off.ok()) << off.error().text();
    EXPECT_EQ(off->motion.stall, Millis(0)) << "0: no stall detection";
}

TEST(ConfigMotion, ErrorsNameTheKeyAndTheRange) {
    EXPECT_THAT(errors_of(R"({"motion": {"tolerance_deg": 0}})"),
                ElementsAre(ErrorWith("motion.tolerance_deg", "from 0.01 to 10", "got 0")));
    EXPECT_THAT(errors_of(R"({"motion": {"tolerance_deg": "0.5"}})"),
                ElementsAre(ErrorWith("motion.tolerance_deg", "from 0.01 to 10")));
    EXPECT_THAT(errors_of(R"({"motion": {"timeout_ms": 50}})"),
                ElementsAre(ErrorWith("motion.timeout_ms", "100", "600000", "got 50")));
    EXPECT_THAT(
        errors_of(R"({"motion": {"timeout": 5000}})"),
        ElementsAre(ErrorWith("motion.timeout", "tolerance_deg", "timeout_ms", "stall_ms")));
    EXPECT_THAT(errors_of(R"({"motion": {"stall_ms": 150}})"),
                ElementsAre(ErrorWith("motion.stall_ms", "0 (off)", "200 to 600000", "got 150")));
    EXPECT_THAT(errors_of(R"({"motion": {"stall_ms": 600001}})"),
                ElementsAre(ErrorWith("motion.stall_ms", "0", "600000", "got 600001")));
}

}  // namespace
}  // namespace gport::config::test
