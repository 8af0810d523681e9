// Tracked angle and centre motions in the core, against the simulated
// gimbal: how each one ends, what a waiter is told, and what the failsafe
// sends when a waiting owner goes away.
#include "core_fixture.hpp"

namespace gport::testing {
namespace {

using config::Failsafe;
using daemon::EndReason;
using daemon::MotionChange;
using daemon::MotionEnd;
using daemon::MotionMode;

class TrackedMotionTest : public CoreFixture {
  protected:
    void start_tracked(std::function<void(config::Config&)> tweak = {}) {
        start({}, [&](config::Config& c) {
            c.motion.timeout = 1500ms;
            if (tweak) {
                tweak(c);
            }
        });
        ASSERT_TRUE(run_until([&] { return link_up() && !recorder.attitude.empty(); }));
    }

    daemon::MotionEndCallback waiter() {
        return [this](const MotionEnd& end) { ends.push_back(end); };
    }

    bool ended() const { return !ends.empty(); }

    std::optional<EndReason> last_end_reason() const {
        for (auto it = recorder.motions.rbegin(); it != recorder.motions.rend(); ++it) {
            if (it->change == MotionChange::kEnded) {
                return it->reason;
            }
        }
        return std::nullopt;
    }

    std::vector<MotionEnd> ends;
};

TEST_F(TrackedMotionTest, AnUnreachableTargetEndsWithTimeoutAndSendsNothing) {
    start_tracked();
    // The simulator's pitch stops at 90°; gportd's soft limits allow 100°.
    ASSERT_TRUE(core->angle(alice, {0, 10000, 0}, false, waiter()).ok());
    ASSERT_TRUE(run_until([&] { return frames_with("0x85") == 1; }));
    ASSERT_TRUE(run_until([&] { return ended(); }, 10s));
    EXPECT_EQ(ends[0].reason, EndReason::kTimeout);
    EXPECT_GE(ends[0].elapsed, 1500ms);
    ASSERT_TRUE(ends[0].attitude);
    EXPECT_EQ(ends[0].attitude->attitude.hall.pitch, 9000) << "stopped at the mechanical limit";
    run_for(100ms);
    EXPECT_EQ(frames_with("0x85"), 1u) << "nothing is sent on timeout";
    EXPECT_FALSE(core->status().motion);
}

TEST_F(TrackedMotionTest, AWaitingOwnerGoneEndsItWithTheFailsafe) {
    start_tracked([](config::Config& c) { c.failsafe.on_owner_gone = Failsafe::kCenter; });
    ASSERT_TRUE(core->angle(alice, {0, 6000, 0}, false, waiter()).ok());
    run_for(100ms);
    const auto zeros = zero_speed_frames();
    core->client_gone(alice);
    EXPECT_EQ(last_end_reason(), EndReason::kOwnerGone);
    ASSERT_TRUE(run_until([&] { return ended() && frames_with("0x85") >= 3; }));
    EXPECT_EQ(ends[0].reason, EndReason::kOwnerGone);
    EXPECT_EQ(zero_speed_frames(), zeros + 1);
    EXPECT_EQ(trace_of("0x85").back().value("mode", ""), "center");
}

TEST_F(TrackedMotionTest, AFireAndForgetAngleOutlivesItsOwner) {
    start_tracked();
    ASSERT_TRUE(core->angle(alice, {0, 3000, 0}).ok());
    core->client_gone(alice);
    core->client_closed(alice);
    EXPECT_TRUE(core->status().motion) << "still tracked";
    ASSERT_TRUE(run_until([&] { return last_end_reason().has_value(); }));
    EXPECT_EQ(last_end_reason(), EndReason::kReached);
    EXPECT_EQ(zero_speed_frames(), 0u);
    EXPECT_NEAR(simulator->model().state().hall.pitch, 30.0, 0.5);
}

TEST_F(TrackedMotionTest, StopSpeedLockAndANewerAngleEndTheMotion) {
    start_tracked();
    ASSERT_TRUE(core->angle(alice, {0, 8000, 0}, false, waiter()).ok());
    ASSERT_TRUE(core->angle(bob, {0, -8000, 0}, false, waiter()).ok());
    EXPECT_EQ(last_end_reason(), EndReason::kReplaced);
    ASSERT_TRUE(core->stop(alice).ok());
    EXPECT_EQ(last_end_reason(), EndReason::kStop);
    ASSERT_TRUE(core->center(alice, waiter()).ok());
    ASSERT_TRUE(core->speed(alice, {0, 0, 100}, 500ms).ok());
    EXPECT_EQ(last_end_reason(), EndReason::kSuperseded);
    ASSERT_TRUE(core->angle(alice, {0, 8000, 0}, false, waiter()).ok());
    EXPECT_EQ(last_end_reason(), EndReason::kSuperseded) << "the speed motion, superseded";
    ASSERT_TRUE(core->lock(alice).ok());
    EXPECT_EQ(last_end_reason(), EndReason::kSuperseded);
    ASSERT_TRUE(run_until([&] { return ends.size() == 4; }));
    EXPECT_EQ(ends[0].reason, EndReason::kReplaced);
    EXPECT_EQ(ends[1].reason, EndReason::kStop);
    EXPECT_EQ(ends[2].reason, EndReason::kSuperseded);
    EXPECT_EQ(ends[3].reason, EndReason::kSuperseded);
}

TEST_F(TrackedMotionTest, AcquireByAnotherClientPreemptsIt) {
    start_tracked();
    ASSERT_TRUE(core->angle(alice, {0, 8000, 0}, false, waiter()).ok());
    ASSERT_TRUE(core->acquire(bob).ok());
    EXPECT_EQ(last_end_reason(), EndReason::kPreempted);
    ASSERT_TRUE(run_until([&] { return ended(); }));
    EXPECT_EQ(ends[0].reason, EndReason::kPreempted);
}

TEST_F(TrackedMotionTest, ShutdownEndsItWithZeroSpeed) {
    start_tracked();
    ASSERT_TRUE(core->angle(alice, {0, 8000, 0}, false, waiter()).ok());
    bool done = false;
    core->shutdown([&] { done = true; });
    ASSERT_TRUE(run_until([&] { return done && ended(); }, 5s));
    core.reset();
    EXPECT_EQ(ends[0].reason, EndReason::kShutdown);
    ASSERT_TRUE(run_until([&] { return zero_speed_frames() == 1; }, 5s));
}

TEST_F(TrackedMotionTest, ReachedWithStatusWhileOnTheWay) {
    start_tracked();
    ASSERT_TRUE(core->center(alice).ok());
    ASSERT_TRUE(run_until([&] { return last_end_reason().has_value(); }));
    ASSERT_TRUE(core->angle(alice, {1000, -2000, 3000}, false, waiter()).ok());
    const auto motion = core->status().motion;
    ASSERT_TRUE(motion);
    EXPECT_EQ(motion->mode, MotionMode::kAngle);
    EXPECT_EQ(motion->target, (protocol::Axes{1000, -2000, 3000}));
    EXPECT_EQ(motion->owner->id, alice.id);
    ASSERT_TRUE(run_until([&] { return ended(); }));
    EXPECT_EQ(ends[0].reason, EndReason::kReached);
    const auto hall = ends[0].attitude->attitude.hall;
    EXPECT_NEAR(hall.roll, 1000, 50);
    EXPECT_NEAR(hall.pitch, -2000, 50);
    EXPECT_NEAR(hall.yaw, 3000, 50);
    EXPECT_FALSE(core->status().motion);
}

TEST_F(TrackedMotionTest, AReloadChangesTheTimeoutOfTheNextMotion) {
    start_tracked();
    auto next = test_config(simulator->device_path());
    next.motion.timeout = 200ms;
    core->reload(next);
    ASSERT_TRUE(core->angle(alice, {0, 10000, 0}, false, waiter()).ok());
    ASSERT_TRUE(run_until([&] { return ended(); }, 5s));
    EXPECT_EQ(ends[0].reason, EndReason::kTimeout);
    EXPECT_LT(ends[0].elapsed, 1500ms);
}

// ---- the centre and the soft limits ----------------------------------------------

void narrow_pitch(config::Config& c) {
    c.limits.pitch = {-60.0, -10.0};  // 0 is outside: a camera that must look down
}

TEST_F(TrackedMotionTest, CenterAimsAtTheCentreClampedIntoTheSoftLimits) {
    start_tracked(narrow_pitch);
    auto sent = core->center(alice, waiter());
    ASSERT_TRUE(sent.ok()) << sent.error().message;
    EXPECT_EQ(sent->angle, (protocol::Axes{0, -1000, 0}));
    EXPECT_EQ(sent->clamped, (std::vector<std::string>{"pitch"}));
    ASSERT_TRUE(run_until([&] { return frames_with("0x85") == 1; }));
    const auto frame = trace_of("0x85").back();
    EXPECT_EQ(frame.value("mode", ""), "angle") << "not the gimbal's own centre";
    EXPECT_EQ(frame["angle"], Json::array({0, -1000, 0}));
    const auto started = recorder.motions.back();
    EXPECT_EQ(started.mode, MotionMode::kCenter);
    EXPECT_EQ(started.clamped, (std::vector<std::string>{"pitch"}));
    ASSERT_TRUE(run_until([&] { return ended(); }));
    EXPECT_EQ(ends[0].reason, EndReason::kReached);
    EXPECT_NEAR(simulator->model().state().hall.pitch, -10.0, 0.5);
}

TEST_F(TrackedMotionTest, WithinTheLimitsCenterSendsTheCentreCommand) {
    start_tracked([](config::Config& c) { c.limits.pitch = {-60.0, 30.0}; });
    auto sent = core->center(alice);
    ASSERT_TRUE(sent.ok());
    EXPECT_TRUE(sent->clamped.empty());
    EXPECT_EQ(sent->angle, (protocol::Axes{0, 0, 0}));
    ASSERT_TRUE(run_until([&] { return frames_with("0x85") == 1; }));
    EXPECT_EQ(trace_of("0x85").back().value("mode", ""), "center");
}

TEST_F(TrackedMotionTest, TheFailsafeCentreIsClampedIntoTheSoftLimitsToo) {
    start_tracked([](config::Config& c) {
        narrow_pitch(c);
        c.failsafe.on_owner_gone = Failsafe::kCenter;
    });
    ASSERT_TRUE(core->angle(alice, {0, -5000, 0}, false, waiter()).ok());
    run_for(100ms);
    core->client_gone(alice);
    ASSERT_TRUE(run_until([&] { return frames_with("0x85") >= 3; }));
    const auto last = trace_of("0x85").back();
    EXPECT_EQ(last.value("mode", ""), "angle");
    EXPECT_EQ(last["angle"], Json::array({0, -1000, 0}));
}

TEST_F(TrackedMotionTest, ACentreStreamFromItsOwnerIsOneMotion) {
    start_tracked();
    for (int i = 0; i < 20; ++i) {  // MAVLink RETRACT, sent every cycle
        ASSERT_TRUE(core->center(alice).ok());
    }
    std::size_t started = 0;
    for (const auto& m : recorder.motions) {
        started += m.change == MotionChange::kStarted ? 1 : 0;
    }
    EXPECT_EQ(started, 1u);
    EXPECT_EQ(core->status().counters.motion_updates, 19u);
}

}  // namespace
}  // namespace gport::testing
