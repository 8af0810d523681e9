// The "realtime" section: priority (0 = off, 1-99 SCHED_FIFO) and lock_memory.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "test_support.hpp"

namespace gport::config {
namespace {

using test::errors_of;
using test::ErrorWith;
using test::load;
using ::testing::ElementsAre;

TEST(ConfigRealtime, OffByDefault) {
    auto c = load("{}");
    ASSERT_TRUE(c);
    EXPECT_EQ(c->realtime.priority, 0);
    EXPECT_FALSE(c->realtime.lock_memory);
}

TEST(ConfigRealtime, PriorityAndLockMemoryAreRead) {
    auto c = load(R"({"realtime": {"priority": 40, "lock_memory": true}})");
    ASSERT_TRUE(c);
    EXPECT_EQ(c->realtime.priority, 40);
    EXPECT_TRUE(c->realtime.lock_memory);
}

TEST(ConfigRealtime, BadValuesNameTheKeyAndWhatIsAllowed) {
    EXPECT_THAT(errors_of(R"({"realtime": {"priority": 100}})"),
                ElementsAre(ErrorWith("realtime.priority", "from 0 to 99", "got 100")));
    EXPECT_THAT(errors_of(R"({"realtime": {"priority": "high"}})"),
                ElementsAre(ErrorWith("realtime.priority", "integer")));
    EXPECT_THAT(errors_of(R"({"realtime": {"lock_memory": 1}})"),
                ElementsAre(ErrorWith("realtime.lock_memory", "must be true or false", "got 1")));
    EXPECT_THAT(errors_of(R"({"realtime": {"nice": 5}})"),
                ElementsAre(ErrorWith("realtime", "nice", "priority", "lock_memory")));
}

}  // namespace
}  // namespace gport::config
