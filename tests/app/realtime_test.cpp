// realtime.priority and realtime.lock_memory at start: what is applied, and
// the warning (never an error) when the system refuses.
#include "gport/app/realtime.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cerrno>

namespace gport::app {
namespace {

using ::testing::AllOf;
using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::IsEmpty;

// What the fake system calls answer and saw.
int g_fifo_error = 0;
int g_current = 0;
int g_lock_error = 0;
int g_set_priority = -1;
int g_locks = 0;

RealtimeCalls fake_calls() {
    return {[](int priority) {
                g_set_priority = priority;
                return g_fifo_error;
            },
            [] { return g_current; },
            [] {
                ++g_locks;
                return g_lock_error;
            }};
}

class RealtimeTest : public ::testing::Test {
  protected:
    void SetUp() override {
        g_fifo_error = g_current = g_lock_error = g_locks = 0;
        g_set_priority = -1;
    }
};

TEST_F(RealtimeTest, OffByDefaultCallsNothing) {
    const auto out = apply_realtime(config::RealtimeConfig{}, fake_calls());
    EXPECT_THAT(out.applied, IsEmpty());
    EXPECT_THAT(out.warnings, IsEmpty());
    EXPECT_EQ(g_set_priority, -1);
    EXPECT_EQ(g_locks, 0);
}

TEST_F(RealtimeTest, AppliesPriorityAndLock) {
    const auto out = apply_realtime(config::RealtimeConfig{30, true}, fake_calls());
    EXPECT_EQ(g_set_priority, 30);
    EXPECT_EQ(g_locks, 1);
    EXPECT_THAT(out.warnings, IsEmpty());
    EXPECT_THAT(out.applied, ElementsAre(HasSubstr("SCHED_FIFO"), HasSubstr("mlockall")));
}

TEST_F(RealtimeTest, RefusalIsAWarningThatSaysWhyAndWhatToDo) {
    g_fifo_error = EPERM;
    g_lock_error = ENOMEM;
    const auto out = apply_realtime(config::RealtimeConfig{30, true}, fake_calls());
    EXPECT_THAT(out.applied, IsEmpty());
    EXPECT_THAT(out.warnings,
                ElementsAre(AllOf(HasSubstr("realtime.priority 30"), HasSubstr("refused"),
                                  HasSubstr("Operation not permitted"),
                                  HasSubstr("normal scheduling"), HasSubstr("LimitRTPRIO")),
                            AllOf(HasSubstr("realtime.lock_memory"), HasSubstr("refused"),
                                  HasSubstr("LimitMEMLOCK"))));
}

TEST_F(RealtimeTest, FifoSetByTheServiceManagerIsLeftAlone) {
    g_current = 50;
    const auto out = apply_realtime(config::RealtimeConfig{30, false}, fake_calls());
    EXPECT_EQ(g_set_priority, -1);
    EXPECT_THAT(out.applied, ElementsAre(HasSubstr("already SCHED_FIFO priority 50")));
}

}  // namespace
}  // namespace gport::app
