#include "gport/ipc/attitude_pacer.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <string>

namespace gport::ipc {
namespace {

using namespace std::chrono_literals;
using Decision = AttitudePacer::Decision;
using Clock = AttitudePacer::Clock;

AttitudeLine sample(int seq) {
    return std::make_shared<const AttitudeNotification>(
        AttitudeNotification{"sample " + std::to_string(seq), {}});
}

class AttitudePacerTest : public ::testing::Test {
  protected:
    const Clock::time_point t0 = Clock::time_point{} + 1h;
    static constexpr Clock::duration kInterval = 100ms;
    AttitudePacer pacer;
};

TEST_F(AttitudePacerTest, TheFirstSampleGoesAtOnce) {
    EXPECT_EQ(pacer.offer(sample(1), t0, kInterval), Decision::kSend);
    EXPECT_FALSE(pacer.holding());
    EXPECT_FALSE(pacer.waking());
}

TEST_F(AttitudePacerTest, SamplesAnIntervalApartAllGoAtOnce) {
    EXPECT_EQ(pacer.offer(sample(1), t0, kInterval), Decision::kSend);
    EXPECT_EQ(pacer.offer(sample(2), t0 + 100ms, kInterval), Decision::kSend);
    EXPECT_EQ(pacer.offer(sample(3), t0 + 250ms, kInterval), Decision::kSend);
}

TEST_F(AttitudePacerTest, ASampleTooSoonIsHeldAndAsksForAWakeOneIntervalAfterTheLastSent) {
    ASSERT_EQ(pacer.offer(sample(1), t0, kInterval), Decision::kSend);
    EXPECT_EQ(pacer.offer(sample(2), t0 + 30ms, kInterval), Decision::kHoldAndWake);
    EXPECT_EQ(pacer.wake_at(), t0 + 100ms);
    EXPECT_TRUE(pacer.holding());
    EXPECT_TRUE(pacer.waking());
}

TEST_F(AttitudePacerTest, OnlyTheNewestHeldSampleGoesAtTheWake) {
    ASSERT_EQ(pacer.offer(sample(1), t0, kInterval), Decision::kSend);
    ASSERT_EQ(pacer.offer(sample(2), t0 + 10ms, kInterval), Decision::kHoldAndWake);
    EXPECT_EQ(pacer.offer(sample(3), t0 + 20ms, kInterval), Decision::kHold);
    EXPECT_EQ(pacer.offer(sample(4), t0 + 30ms, kInterval), Decision::kHold);
    const auto sent = pacer.woken(t0 + 100ms);
    ASSERT_NE(sent, nullptr);
    EXPECT_EQ(sent->text, "sample 4");
    EXPECT_FALSE(pacer.holding());
    EXPECT_FALSE(pacer.waking());
}

TEST_F(AttitudePacerTest, WhileAWakeIsPendingEvenALateSampleWaitsForIt) {
    ASSERT_EQ(pacer.offer(sample(1), t0, kInterval), Decision::kSend);
    ASSERT_EQ(pacer.offer(sample(2), t0 + 10ms, kInterval), Decision::kHoldAndWake);
    // The timer is late: the sample that arrives meanwhile joins the held one.
    EXPECT_EQ(pacer.offer(sample(3), t0 + 150ms, kInterval), Decision::kHold);
    EXPECT_EQ(pacer.woken(t0 + 160ms)->text, "sample 3");
}

TEST_F(AttitudePacerTest, TheIntervalCountsFromTheWake) {
    ASSERT_EQ(pacer.offer(sample(1), t0, kInterval), Decision::kSend);
    ASSERT_EQ(pacer.offer(sample(2), t0 + 10ms, kInterval), Decision::kHoldAndWake);
    ASSERT_NE(pacer.woken(t0 + 120ms), nullptr);
    EXPECT_EQ(pacer.offer(sample(3), t0 + 200ms, kInterval), Decision::kHoldAndWake);
    EXPECT_EQ(pacer.wake_at(), t0 + 220ms);
    EXPECT_EQ(pacer.offer(sample(4), t0 + 220ms, kInterval), Decision::kHold);
}

TEST_F(AttitudePacerTest, AWakeWithNothingHeldSendsNothingAndKeepsTheLastSendTime) {
    ASSERT_EQ(pacer.offer(sample(1), t0, kInterval), Decision::kSend);
    ASSERT_EQ(pacer.offer(sample(2), t0 + 10ms, kInterval), Decision::kHoldAndWake);
    pacer.clear();
    EXPECT_EQ(pacer.woken(t0 + 100ms), nullptr);
    EXPECT_FALSE(pacer.waking());
    EXPECT_EQ(pacer.offer(sample(3), t0 + 100ms, kInterval), Decision::kSend);
}

TEST_F(AttitudePacerTest, ACancelledWakeLetsTheNextSampleAskForAnother) {
    ASSERT_EQ(pacer.offer(sample(1), t0, kInterval), Decision::kSend);
    ASSERT_EQ(pacer.offer(sample(2), t0 + 10ms, kInterval), Decision::kHoldAndWake);
    pacer.disarmed();
    EXPECT_TRUE(pacer.holding());
    EXPECT_EQ(pacer.offer(sample(3), t0 + 20ms, kInterval), Decision::kHoldAndWake);
    EXPECT_EQ(pacer.woken(t0 + 100ms)->text, "sample 3");
}

TEST_F(AttitudePacerTest, ALongerIntervalAppliesToTheNextDecision) {
    ASSERT_EQ(pacer.offer(sample(1), t0, kInterval), Decision::kSend);
    EXPECT_EQ(pacer.offer(sample(2), t0 + 150ms, 1s), Decision::kHoldAndWake);
    EXPECT_EQ(pacer.wake_at(), t0 + 1s);
}

}  // namespace
}  // namespace gport::ipc
