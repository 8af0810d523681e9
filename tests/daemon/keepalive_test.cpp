// The speed motion's schedule (Keepalive, state only: Motion owns its timer)
// and the one freshness rule, driven with made-up times: no timer, no device.
#include "gport/daemon/core/keepalive.hpp"

#include <gtest/gtest.h>

#include "gport/daemon/core/motion.hpp"

namespace gport::daemon {
namespace {

using namespace std::chrono_literals;
using protocol::Axes;
using Due = Keepalive::Due;

const ClientInfo kAlice{1, 1001, 1001, 1001, {}};
const ClientInfo kBob{2, 1002, 1002, 1002, {}};
const SteadyTime kT0 = SteadyTime{} + 1h;

TEST(Freshness, ASampleIsFreshOnlyWhileYoungerThanStaleMs) {
    EXPECT_TRUE(is_fresh(0ms, 500ms));
    EXPECT_TRUE(is_fresh(499ms, 500ms));
    EXPECT_FALSE(is_fresh(500ms, 500ms)) << "exactly link.stale_ms old is stale, as for the link";
    EXPECT_FALSE(is_fresh(501ms, 500ms));
}

TEST(Keepalive, NothingRunsUntilStarted) {
    Keepalive k(100ms);
    EXPECT_FALSE(k.active());
    EXPECT_EQ(k.due(kT0), Due::kNothing);
    EXPECT_FALSE(k.tick(kT0).has_value());
    EXPECT_FALSE(k.note(kT0).has_value());
    EXPECT_FALSE(k.end(EndReason::kStop).has_value()) << "no ended event without a motion";
    EXPECT_FALSE(k.brake({0, 0, 0}, {"yaw"}, kT0).has_value());
}

TEST(Keepalive, TicksAreDriftFreeAndAStallSkipsMissedTicks) {
    Keepalive k(100ms);
    const auto started = k.start(kAlice, {0, 0, 500}, 10s, 10s, {}, kT0);
    ASSERT_TRUE(started.event.has_value());
    EXPECT_EQ(started.event->change, MotionChange::kStarted);
    EXPECT_EQ(k.due(kT0 + 99ms), Due::kNothing);
    EXPECT_EQ(k.wake_at(), kT0 + 100ms);
    ASSERT_EQ(k.due(kT0 + 130ms), Due::kTick);
    EXPECT_EQ(k.tick(kT0 + 130ms), (Axes{0, 0, 500}));
    EXPECT_EQ(k.wake_at(), kT0 + 200ms) << "from the previous deadline, not from the late tick";
    EXPECT_EQ(k.tick(kT0 + 650ms), (Axes{0, 0, 500})) << "one frame after a stall, no burst";
    EXPECT_EQ(k.wake_at(), kT0 + 700ms);
    EXPECT_FALSE(k.tick(kT0 + 650ms).has_value()) << "nothing is due twice";
}

TEST(Keepalive, TheEndComesBeforeTheLeaseAndTheLeaseBeforeATick) {
    Keepalive k(100ms);
    (void)k.start(kAlice, {0, 0, 500}, 1000ms, 300ms, {}, kT0);
    EXPECT_EQ(k.due(kT0 + 300ms), Due::kLeaseEnd) << "a tick is also due: the lease wins";
    EXPECT_EQ(k.due(kT0 + 1000ms), Due::kEnd);
    const auto ended = k.end(EndReason::kDuration);
    ASSERT_TRUE(ended.has_value());
    EXPECT_EQ(ended->change, MotionChange::kEnded);
    EXPECT_EQ(ended->reason, EndReason::kDuration);
    EXPECT_FALSE(k.active());
}

TEST(Keepalive, AnotherOwnersSpeedReplacesTheOwnersOwnIsACoalescedUpdate) {
    Keepalive k(100ms);
    (void)k.start(kAlice, {0, 0, 500}, 10s, 10s, {}, kT0);
    const auto update = k.start(kAlice, {0, 0, 600}, 10s, 10s, {}, kT0 + 50ms);
    EXPECT_FALSE(update.event.has_value()) << "within kUpdateNoteInterval: published later";
    EXPECT_EQ(k.updates(), 1U);
    EXPECT_FALSE(k.note(kT0 + 499ms).has_value());
    EXPECT_EQ(k.wake_at(), kT0 + 150ms) << "the update's frame counts as a tick";
    const auto note = k.note(kT0 + Keepalive::kUpdateNoteInterval);
    ASSERT_TRUE(note.has_value());
    EXPECT_EQ(note->change, MotionChange::kUpdated);
    EXPECT_EQ(note->speed.yaw, 600) << "the latest speed";
    const auto replaced = k.start(kBob, {0, 0, -500}, 10s, 10s, {}, kT0 + 600ms);
    ASSERT_TRUE(replaced.event.has_value());
    EXPECT_EQ(replaced.event->change, MotionChange::kReplaced);
    EXPECT_EQ(k.owner()->id, kBob.id);
}

TEST(Keepalive, AnUpdateThatBrakesANewAxisIsPublishedAtOnce) {
    Keepalive k(100ms);
    (void)k.start(kAlice, {0, 500, 500}, 10s, 10s, {}, kT0);
    const auto update = k.start(kAlice, {0, 0, 500}, 10s, 10s, {"pitch"}, kT0 + 10ms);
    ASSERT_TRUE(update.event.has_value());
    EXPECT_EQ(update.event->reason, EndReason::kLimit);
    EXPECT_EQ(update.event->braked, std::vector<std::string>{"pitch"});
}

TEST(Keepalive, ABrakeCountsAsATickAndBrakingEveryAxisLeavesNothingToSend) {
    Keepalive k(100ms);
    (void)k.start(kAlice, {0, 500, 500}, 10s, 10s, {}, kT0);
    const auto braked = k.brake({0, 0, 500}, {"pitch"}, kT0 + 120ms);
    ASSERT_TRUE(braked.has_value());
    EXPECT_EQ(braked->change, MotionChange::kUpdated);
    EXPECT_EQ(braked->reason, EndReason::kLimit);
    EXPECT_EQ(braked->speed, (Axes{0, 0, 500}));
    EXPECT_FALSE(k.tick(kT0 + 120ms).has_value()) << "the braked frame just went out";
    EXPECT_FALSE(k.brake({0, 0, 0}, {"yaw"}, kT0 + 130ms).has_value()) << "nothing moves";
    const auto ended = k.end(EndReason::kLimit);
    ASSERT_TRUE(ended.has_value());
    EXPECT_EQ(ended->braked, (std::vector<std::string>{"pitch", "yaw"}));
}

}  // namespace
}  // namespace gport::daemon
