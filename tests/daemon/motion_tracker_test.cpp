// MotionTracker on its own: samples fed by hand, no gimbal. Arrival is the
// pure rule (two consecutive samples within the tolerance); the tracker adds
// the timeout, the end reasons, the events and the waiter's callback.
#include "gport/daemon/core/motion_tracker.hpp"

#include <gtest/gtest.h>

#include <boost/asio/io_context.hpp>
#include <vector>

namespace gport::daemon {
namespace {

using namespace std::chrono_literals;
using protocol::Axes;

TEST(Arrival, OneSampleWithinIsNotEnough) {
    Arrival a({0, 1000, 0}, 0.5);
    EXPECT_FALSE(a.observe({0, 1000, 0}));
    EXPECT_FALSE(a.arrived());
}

TEST(Arrival, OneSampleWithinThenOneOutStartsAgain) {
    Arrival a({0, 1000, 0}, 0.5);
    EXPECT_FALSE(a.observe({0, 1040, 0}));
    EXPECT_FALSE(a.observe({0, 1060, 0})) << "0.6° off: outside 0.5°";
    EXPECT_FALSE(a.observe({0, 1000, 0})) << "the count started again";
    EXPECT_TRUE(a.observe({0, 1000, 0}));
}

TEST(Arrival, TwoConsecutiveSamplesWithinOnEveryAxis) {
    Arrival a({-500, 1000, 17000}, 0.5);
    EXPECT_FALSE(a.observe({-450, 1050, 16950}));
    EXPECT_TRUE(a.observe({-550, 950, 17050}));
    EXPECT_TRUE(a.observe({0, 0, 0})) << "arrived stays arrived";
}

TEST(Arrival, EveryAxisCounts) {
    EXPECT_FALSE(Arrival::within({100, 0, 0}, {0, 0, 0}, 50));
    EXPECT_FALSE(Arrival::within({0, -100, 0}, {0, 0, 0}, 50));
    EXPECT_FALSE(Arrival::within({0, 0, 100}, {0, 0, 0}, 50));
    EXPECT_TRUE(Arrival::within({50, -50, 50}, {0, 0, 0}, 50));
    // The widest gap the protocol allows does not overflow.
    EXPECT_FALSE(Arrival::within({32767, 0, 0}, {-32768, 0, 0}, 50));
}

class TrackerTest : public ::testing::Test {
  protected:
    AttitudeSample sample(Axes hall) {
        AttitudeSample s;
        s.seq = ++seq_;
        s.received = std::chrono::steady_clock::now();
        s.attitude.hall = hall;
        return s;
    }

    MotionEndCallback waiter() {
        return [this](const MotionEnd& end) { ends.push_back(end); };
    }

    // As Core does: the newest sample first, then the tracker offered it.
    void feed(Axes hall, int times = 1) {
        for (int i = 0; i < times; ++i) {
            latest = sample(hall);
            tracker.on_attitude(*latest);
        }
    }

    std::optional<EndReason> last_end_reason() const {
        if (events.empty() || events.back().change != MotionChange::kEnded) {
            return std::nullopt;
        }
        return events.back().reason;
    }

    boost::asio::io_context io;
    std::vector<MotionEvent> events;
    std::vector<MotionEnd> ends;
    std::optional<AttitudeSample> latest;
    MotionTracker tracker{
        io, {0.5, 200ms}, [this](const MotionEvent& e) { events.push_back(e); }, latest};
    ClientInfo alice{1, 1001, 1001, 1001, {}};
    ClientInfo bob{2, 1002, 1002, 1002, {}};
    std::uint64_t seq_ = 0;
};

TEST_F(TrackerTest, TimeoutEndsTheMotionAndTellsTheWaiter) {
    tracker.start(alice, MotionMode::kAngle, {0, 9000, 0}, waiter());
    feed({0, 0, 0}, 3);  // never gets there
    io.run_for(500ms);
    EXPECT_FALSE(tracker.active());
    EXPECT_EQ(last_end_reason(), EndReason::kTimeout);
    ASSERT_EQ(ends.size(), 1u);
    EXPECT_EQ(ends[0].reason, EndReason::kTimeout);
    ASSERT_TRUE(ends[0].attitude);
    EXPECT_EQ(ends[0].attitude->seq, 3u) << "the latest sample";
    EXPECT_GE(ends[0].elapsed, 200ms);
}

TEST_F(TrackerTest, OneSampleWithinThenOutDoesNotEndIt) {
    tracker.start(alice, MotionMode::kAngle, {0, 1000, 0}, waiter());
    feed({0, 1000, 0});
    feed({0, 2000, 0});
    feed({0, 1000, 0});
    EXPECT_TRUE(tracker.active());
    EXPECT_EQ(events.size(), 1u) << "only started";
}

TEST_F(TrackerTest, TwoSamplesWithinEndItReachedWithTheWaiterCalledLater) {
    tracker.start(alice, MotionMode::kAngle, {0, 1000, 0}, waiter());
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].change, MotionChange::kStarted);
    EXPECT_EQ(events[0].mode, MotionMode::kAngle);
    EXPECT_EQ(events[0].angle, (Axes{0, 1000, 0}));
    feed({0, 990, 0}, 2);
    EXPECT_FALSE(tracker.active());
    EXPECT_EQ(last_end_reason(), EndReason::kReached);
    EXPECT_TRUE(ends.empty()) << "never from inside the call that ended it";
    io.poll();
    ASSERT_EQ(ends.size(), 1u);
    EXPECT_EQ(ends[0].reason, EndReason::kReached);
    EXPECT_EQ(ends[0].attitude->attitude.hall, (Axes{0, 990, 0}));
}

TEST_F(TrackerTest, CentreTargetsZero) {
    tracker.start(alice, MotionMode::kCenter, {}, waiter());
    feed({0, 0, 40}, 2);
    io.poll();
    ASSERT_EQ(ends.size(), 1u);
    EXPECT_EQ(ends[0].reason, EndReason::kReached);
    EXPECT_EQ(events.back().mode, MotionMode::kCenter);
}

TEST_F(TrackerTest, ANewerMotionReplacesTheRunningOne) {
    tracker.start(alice, MotionMode::kAngle, {0, 1000, 0}, waiter());
    tracker.start(bob, MotionMode::kCenter, {});
    ASSERT_EQ(events.size(), 3u);
    EXPECT_EQ(events[1].change, MotionChange::kEnded);
    EXPECT_EQ(events[1].reason, EndReason::kReplaced);
    EXPECT_EQ(events[1].owner->id, alice.id);
    EXPECT_EQ(events[2].change, MotionChange::kStarted);
    EXPECT_EQ(tracker.owner()->id, bob.id);
    EXPECT_FALSE(tracker.waiting()) << "bob does not wait";
    io.poll();
    ASSERT_EQ(ends.size(), 1u);
    EXPECT_EQ(ends[0].reason, EndReason::kReplaced);
}

TEST_F(TrackerTest, EachReasonFromOutsideEndsItOnce) {
    for (auto reason : {EndReason::kStop, EndReason::kOwnerGone, EndReason::kSuperseded,
                        EndReason::kPreempted, EndReason::kLinkDown, EndReason::kShutdown}) {
        tracker.start(alice, MotionMode::kAngle, {0, 1000, 0}, waiter());
        tracker.end(reason);
        tracker.end(EndReason::kStop);  // nothing left to end
        EXPECT_EQ(last_end_reason(), reason);
    }
    io.poll();
    ASSERT_EQ(ends.size(), 6u);
    EXPECT_EQ(ends.back().reason, EndReason::kShutdown);
    EXPECT_FALSE(ends.back().attitude) << "no sample yet";
}

TEST_F(TrackerTest, TheTimeoutOfAnEndedMotionDoesNothing) {
    tracker.start(alice, MotionMode::kAngle, {0, 9000, 0}, waiter());
    tracker.end(EndReason::kStop);
    tracker.start(alice, MotionMode::kAngle, {0, 9000, 0});
    io.run_for(100ms);
    EXPECT_TRUE(tracker.active()) << "the second motion has its own timeout";
    io.run_for(300ms);
    EXPECT_FALSE(tracker.active());
    EXPECT_EQ(ends.size(), 1u);
}

TEST_F(TrackerTest, StatusShowsModeTargetOwnerAndElapsed) {
    EXPECT_FALSE(tracker.status());
    tracker.start(alice, MotionMode::kAngle, {100, 200, 300});
    io.run_for(20ms);
    auto s = tracker.status();
    ASSERT_TRUE(s);
    EXPECT_EQ(s->mode, MotionMode::kAngle);
    EXPECT_EQ(s->target, (Axes{100, 200, 300}));
    EXPECT_EQ(s->owner->id, alice.id);
    EXPECT_GE(s->elapsed, 20ms);
}

TEST_F(TrackerTest, OptionsApplyToTheNextMotion) {
    tracker.set_options({2.0, 200ms});
    tracker.start(alice, MotionMode::kAngle, {0, 1000, 0});
    feed({0, 1150, 0}, 2);  // 1.5° off: within 2°
    EXPECT_EQ(last_end_reason(), EndReason::kReached);
}

// ---- updates: a client streaming targets ------------------------------------------

std::size_t count(const std::vector<MotionEvent>& events, MotionChange change) {
    std::size_t n = 0;
    for (const auto& e : events) {
        n += e.change == change ? 1 : 0;
    }
    return n;
}

TEST_F(TrackerTest, AnAngleFromTheOwnerUpdatesItsMotionQuietly) {
    tracker.set_options({0.5, 5s});
    tracker.start(alice, MotionMode::kAngle, {0, 0, 0});
    for (std::int16_t i = 1; i <= 50; ++i) {  // a 50 Hz pan: one second of targets
        tracker.start(alice, MotionMode::kAngle, {0, 0, static_cast<std::int16_t>(i * 10)});
    }
    EXPECT_EQ(count(events, MotionChange::kStarted), 1u);
    EXPECT_EQ(count(events, MotionChange::kEnded), 0u) << "nothing replaced";
    EXPECT_EQ(count(events, MotionChange::kUpdated), 0u) << "coalesced: not yet";
    EXPECT_EQ(tracker.updates(), 50u);
    EXPECT_EQ(tracker.status()->target, (Axes{0, 0, 500}));
    io.run_for(600ms);
    ASSERT_EQ(count(events, MotionChange::kUpdated), 1u) << "one event for all fifty";
    EXPECT_EQ(events.back().angle, (Axes{0, 0, 500})) << "it carries the latest target";
    EXPECT_EQ(events.back().owner->id, alice.id);
}

TEST_F(TrackerTest, UpdatesArePublishedAtMostTwiceASecond) {
    tracker.set_options({0.5, 5s});
    tracker.start(alice, MotionMode::kAngle, {0, 0, 0});
    const auto until = std::chrono::steady_clock::now() + 1300ms;
    std::int16_t yaw = 0;
    while (std::chrono::steady_clock::now() < until) {
        yaw = static_cast<std::int16_t>(yaw + 10);
        tracker.start(alice, MotionMode::kAngle, {0, 0, yaw});
        io.run_for(20ms);
    }
    const auto updated = count(events, MotionChange::kUpdated);
    EXPECT_GE(updated, 1u);
    EXPECT_LE(updated, 3u) << "1.3 s of updates: at most one per 500 ms";
}

TEST_F(TrackerTest, AnUpdatedMotionArrivesAtItsNewTargetOnceTheStreamPauses) {
    tracker.set_options({0.5, 5s});
    tracker.start(alice, MotionMode::kAngle, {0, 1000, 0});
    feed({0, 1000, 0});  // one sample at the old target
    tracker.start(alice, MotionMode::kAngle, {0, 2000, 0});
    feed({0, 1000, 0});
    feed({0, 2000, 0}, 3);
    EXPECT_TRUE(tracker.active()) << "there, but the stream may go on: not yet reached";
    io.run_for(MotionTracker::kUpdateNoteInterval);
    feed({0, 1000, 0});
    EXPECT_TRUE(tracker.active()) << "the old target no longer counts";
    feed({0, 2000, 0}, 2);
    EXPECT_EQ(last_end_reason(), EndReason::kReached);
    EXPECT_EQ(events.back().angle, (Axes{0, 2000, 0}));
}

TEST_F(TrackerTest, AStreamThatKeepsItsTargetsWithinTheToleranceIsStillOneMotion) {
    tracker.set_options({0.5, 5s});
    tracker.start(alice, MotionMode::kAngle, {0, 0, 0});
    for (std::int16_t yaw = 10; yaw <= 200; yaw = static_cast<std::int16_t>(yaw + 10)) {
        tracker.start(alice, MotionMode::kAngle, {0, 0, yaw});  // 0.1° steps
        feed({0, 0, static_cast<std::int16_t>(yaw - 10)}, 2);   // the gimbal keeps up
    }
    EXPECT_TRUE(tracker.active());
    EXPECT_EQ(count(events, MotionChange::kEnded), 0u);
}

TEST_F(TrackerTest, TheTimeoutRunsFromTheLastUpdate) {
    tracker.start(alice, MotionMode::kAngle, {0, 9000, 0});  // timeout 200 ms
    io.run_for(150ms);
    tracker.start(alice, MotionMode::kAngle, {0, 9100, 0});
    io.run_for(150ms);
    EXPECT_TRUE(tracker.active()) << "300 ms after the start, 150 ms after the update";
    io.run_for(200ms);
    EXPECT_EQ(last_end_reason(), EndReason::kTimeout);
}

TEST_F(TrackerTest, AMotionSomebodyWaitsForIsReplacedNotUpdated) {
    tracker.start(alice, MotionMode::kAngle, {0, 1000, 0}, waiter());
    tracker.start(alice, MotionMode::kAngle, {0, 2000, 0});
    EXPECT_EQ(events[1].change, MotionChange::kEnded);
    EXPECT_EQ(events[1].reason, EndReason::kReplaced);
    EXPECT_EQ(tracker.updates(), 0u);
    io.poll();
    ASSERT_EQ(ends.size(), 1u) << "the waiter gets its answer";
    EXPECT_EQ(ends[0].reason, EndReason::kReplaced);
}

TEST_F(TrackerTest, AnotherClientOrAnotherModeReplaces) {
    tracker.start(alice, MotionMode::kAngle, {0, 1000, 0});
    tracker.start(bob, MotionMode::kAngle, {0, 2000, 0});
    tracker.start(bob, MotionMode::kCenter, {});
    EXPECT_EQ(count(events, MotionChange::kStarted), 3u);
    EXPECT_EQ(count(events, MotionChange::kEnded), 2u);
    EXPECT_EQ(tracker.updates(), 0u);
}

TEST_F(TrackerTest, AnUpdateMayStartWaitingAndIsToldTheEnd) {
    tracker.set_options({0.5, 5s});
    tracker.start(alice, MotionMode::kCenter, {});
    tracker.start(alice, MotionMode::kCenter, {}, waiter());
    EXPECT_EQ(tracker.updates(), 1u);
    EXPECT_TRUE(tracker.waiting());
    io.run_for(MotionTracker::kUpdateNoteInterval);
    feed({0, 0, 0}, 2);
    io.poll();
    ASSERT_EQ(ends.size(), 1u);
    EXPECT_EQ(ends[0].reason, EndReason::kReached);
}

TEST_F(TrackerTest, TheClampedAxesAreToldInTheEvents) {
    tracker.start(alice, MotionMode::kCenter, {0, -1000, 0}, {}, {"pitch"});
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].clamped, (std::vector<std::string>{"pitch"}));
    tracker.end(EndReason::kStop);
    EXPECT_EQ(events.back().clamped, (std::vector<std::string>{"pitch"}));
}

// ---- stalls ---------------------------------------------------------------------

const auto t0 = std::chrono::steady_clock::time_point{} + std::chrono::hours(1);

TEST(Progress, NoProgressForTheWindowIsAStall) {
    Progress p({0, -10000, 0}, t0, 2000ms);
    EXPECT_FALSE(p.stalled({0, -8000, 0}, t0 + 100ms));
    EXPECT_FALSE(p.stalled({0, -9000, 0}, t0 + 1000ms)) << "progress";
    EXPECT_FALSE(p.stalled({0, -9000, 0}, t0 + 2999ms));
    EXPECT_TRUE(p.stalled({0, -9000, 0}, t0 + 3000ms)) << "2 s since the last progress";
    EXPECT_EQ(p.where(), "pitch -90.00 (target -100.00, 10.00° short)");
}

TEST(Progress, JitterAroundAStopIsNoProgress) {
    Progress p({0, 0, 17500}, t0, 500ms);
    EXPECT_FALSE(p.stalled({0, 0, 17000}, t0));
    // ±0.09°: a new smallest distance, but less than Progress::kStep below it.
    EXPECT_FALSE(p.stalled({0, 0, 17009}, t0 + 200ms));
    EXPECT_FALSE(p.stalled({0, 0, 16991}, t0 + 400ms));
    EXPECT_TRUE(p.stalled({0, 0, 17009}, t0 + 500ms));
    EXPECT_EQ(p.where(), "yaw 170.09 (target 175.00, 4.91° short)");
}

TEST(Progress, TheFarthestAxisIsTheDistanceAndAZeroWindowNeverStalls) {
    Progress p({-4500, 3000, 0}, t0, 0ms);
    EXPECT_FALSE(p.stalled({-4400, 0, 0}, t0));
    EXPECT_FALSE(p.stalled({-4400, 0, 0}, t0 + 3600s)) << "off";
    // Roll at its end 1° short, pitch moving: progress while pitch closes in.
    Progress q({-4500, 3000, 0}, t0, 1000ms);
    EXPECT_FALSE(q.stalled({-4400, 0, 0}, t0));
    EXPECT_FALSE(q.stalled({-4400, 2000, 0}, t0 + 900ms));
    EXPECT_FALSE(q.stalled({-4400, 2950, 0}, t0 + 1800ms)) << "pitch within 0.5°, roll 1° off";
    EXPECT_TRUE(q.stalled({-4400, 2950, 0}, t0 + 2800ms));
    EXPECT_EQ(q.where(), "roll -44.00 (target -45.00, 1.00° short)");
}

// A tracker with a 500 ms stall window (and a timeout that never comes);
// offer() stamps each sample `at` after the motion started.
class StallTest : public TrackerTest {
  protected:
    void start(Axes target, MotionEndCallback on_end = {}) {
        stalling.start(alice, MotionMode::kAngle, target, std::move(on_end));
        started = std::chrono::steady_clock::now();
    }
    void offer(Axes hall, std::chrono::milliseconds at) {
        latest = sample(hall);
        latest->received = started + at;
        stalling.on_attitude(*latest);
    }

    MotionTracker stalling{
        io, {0.5, 60000ms, 500ms}, [this](const MotionEvent& e) { events.push_back(e); }, latest};
    std::chrono::steady_clock::time_point started;
};

TEST_F(StallTest, AStalledMotionEndsSayingWhereTheGimbalStopped) {
    start({0, -10000, 0}, waiter());
    offer({0, -5000, 0}, 100ms);
    offer({0, -9000, 0}, 300ms);
    offer({0, -9000, 0}, 700ms);
    EXPECT_TRUE(stalling.active());
    offer({0, -9000, 0}, 800ms);
    ASSERT_FALSE(stalling.active());
    ASSERT_EQ(events.back().change, MotionChange::kEnded);
    EXPECT_EQ(events.back().reason, EndReason::kStalled);
    const std::string detail =
        "stalled at pitch -90.00 (target -100.00, 10.00° short): no progress for 500 ms; "
        "beyond the gimbal's reach, or blocked?";
    EXPECT_EQ(events.back().detail, detail);
    io.poll();
    ASSERT_EQ(ends.size(), 1u);
    EXPECT_EQ(ends[0].reason, EndReason::kStalled);
    EXPECT_EQ(ends[0].detail, detail);
    EXPECT_EQ(to_string(EndReason::kStalled), "stalled");
}

TEST_F(StallTest, AnUpdateStartsTheWindowAgain) {
    start({0, -10000, 0});
    offer({0, -9000, 0}, 0ms);
    stalling.start(alice, MotionMode::kAngle, {0, -8000, 0});  // an update: a new target
    offer({0, -9000, 0}, 400ms);
    offer({0, -9000, 0}, 600ms);
    EXPECT_TRUE(stalling.active()) << "the window runs from the update's first sample";
}

}  // namespace
}  // namespace gport::daemon
