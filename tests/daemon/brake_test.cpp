// Issue 12, item 1b: braking at the soft limits during speed motions, with
// the simulated gimbal's attitude (hall angles). An axis moving towards a
// narrowed limit is zeroed within the braking distance of it and the others
// keep moving; nothing is ever sent that drives further past a limit; with
// no fresh attitude a motion that needs it is refused or ends (no_attitude).
#include <algorithm>

#include "core_fixture.hpp"
#include "gport/daemon/core/soft_brake.hpp"

namespace gport::testing {
namespace {

using daemon::EndReason;
using daemon::ErrorCode;
using daemon::MotionChange;
using daemon::MotionEvent;

constexpr double kMargin = 1.0;  // limits.braking_margin_deg in these tests

class Brake : public CoreFixture {
  protected:
    // The simulator on its defaults (pitch ±90° mechanically), the core with
    // a soft pitch range.
    void start_limited(double pitch_min, double pitch_max, sim::SimOptions options = {},
                       config::Failsafe on_link_lost = config::Failsafe::kStop) {
        start(std::move(options), [&](config::Config& c) {
            c.limits.pitch = {pitch_min, pitch_max};
            c.limits.braking_margin_deg = kMargin;
            c.failsafe.on_link_lost = on_link_lost;
        });
        ASSERT_TRUE(run_until([&] { return link_up() && !recorder.attitude.empty(); }));
    }

    // The simulated gimbal's own joint angles, degrees.
    sim::Vec3 hall() const { return simulator->model().state().hall; }

    std::optional<MotionEvent> event_with(EndReason reason) const {
        for (const auto& e : recorder.motions) {
            if (e.reason == reason) {
                return e;
            }
        }
        return std::nullopt;
    }

    // The braking distance the core uses at `speed_deg_s`, for a sample up
    // to `age` old (the default keepalive period, 100 ms, looks ahead).
    static double distance(double speed_deg_s, std::chrono::milliseconds age = 40ms) {
        config::LimitsConfig limits;
        limits.braking_margin_deg = kMargin;
        return daemon::SoftBrake(limits, 100ms).distance(speed_deg_s, age);
    }

    bool ended() const {
        return !recorder.motions.empty() && recorder.motions.back().change == MotionChange::kEnded;
    }
};

// Unhappy paths first: no fresh attitude, or already beyond the limit.

TEST_F(Brake, WithoutAttitudeASpeedTowardsANarrowedLimitIsRefused) {
    sim::SimOptions options;
    options.model.stream_rate_hz = 0;  // telemetry off: never a sample
    start(options, [](config::Config& c) { c.limits.pitch = {-30, 20}; });
    ASSERT_TRUE(run_until([&] { return core->status().device_open; }));
    const auto refused = core->speed(alice, {0, 1000, 0}, 5000ms);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, ErrorCode::kLinkDown);
    EXPECT_NE(refused.error().message.find("no fresh attitude"), std::string::npos)
        << refused.error().message;
    EXPECT_NE(refused.error().message.find("braking pitch"), std::string::npos)
        << refused.error().message;
    EXPECT_NE(refused.error().message.find("none has arrived yet"), std::string::npos)
        << refused.error().message;
    // Axes without a narrowed limit need no attitude: as before.
    EXPECT_TRUE(core->speed(alice, {0, 0, 1000}, 5000ms).ok());
    run_for(100ms);
    EXPECT_TRUE(std::ranges::none_of(speed_frames(), [](const Json& s) { return s[1] != 0; }))
        << "no pitch speed may reach the gimbal";
}

TEST_F(Brake, ASpeedOutwardsFromBeyondALimitIsZeroedAtOnce) {
    start_limited(5, 20);  // the gimbal rests at 0, below the soft minimum 5
    const auto outwards = core->speed(alice, {0, -1000, 0}, 5000ms);
    ASSERT_TRUE(outwards.ok()) << outwards.error().message;
    EXPECT_EQ(outwards->speed, (protocol::Axes{0, 0, 0})) << "the speed sent";
    EXPECT_EQ(outwards->braked, std::vector<std::string>{"pitch"});
    EXPECT_EQ(outwards->duration, 0ms) << "nothing moves";
    EXPECT_FALSE(core->status().motion.has_value());
    EXPECT_TRUE(recorder.motions.empty()) << "no motion started, so no event";

    // With another axis moving: that one moves, pitch stays at zero.
    const auto mixed = core->speed(alice, {0, -1000, 1500}, 5000ms);
    ASSERT_TRUE(mixed.ok());
    EXPECT_EQ(mixed->speed, (protocol::Axes{0, 0, 1500}));
    EXPECT_EQ(mixed->braked, std::vector<std::string>{"pitch"});
    ASSERT_TRUE(core->status().motion.has_value());
    run_for(300ms);
    EXPECT_TRUE(std::ranges::none_of(speed_frames(), [](const Json& s) { return s[1] < 0; }))
        << "a speed driving further past the limit reached the gimbal";
    EXPECT_GT(hall().yaw, 1.0);
    EXPECT_EQ(hall().pitch, 0.0);

    // Inwards is allowed.
    const auto inwards = core->speed(alice, {0, 1000, 0}, 5000ms);
    ASSERT_TRUE(inwards.ok());
    EXPECT_TRUE(inwards->braked.empty());
    EXPECT_EQ(inwards->speed.pitch, 1000);
}

TEST_F(Brake, AStaleLinkEndsAMotionThatBrakesByTheAttitude) {
    sim::SimOptions options;
    options.faults.silence_every = 1500ms;
    options.faults.silence_for = 3000ms;
    start_limited(-60, 60, options);
    // Retry if the silence began between the link coming up and the command.
    ASSERT_TRUE(run_until([&] { return core->speed(alice, {0, 300, 0}, 30000ms).ok(); }));
    ASSERT_TRUE(run_until([&] { return ended(); }, 5s));
    EXPECT_EQ(recorder.motions.back().reason, EndReason::kNoAttitude);
    EXPECT_EQ(core->status().link, daemon::LinkState::kStale);
    ASSERT_TRUE(run_until([&] { return zero_speed_frames() >= 1; }, 2s)) << "zero speed sent";
    EXPECT_EQ(frames_with("0x85") - speed_frames().size(), 0U) << "stop: no other frame";
}

TEST_F(Brake, WithoutANarrowedLimitAStaleLinkChangesNothing) {
    sim::SimOptions options;
    options.faults.silence_every = 1500ms;
    options.faults.silence_for = 3000ms;
    start_limited(-327.67, 327.67, options);
    ASSERT_TRUE(run_until([&] { return core->speed(alice, {0, 300, 0}, 30000ms).ok(); }));
    ASSERT_TRUE(run_until([&] { return core->status().link == daemon::LinkState::kStale; }, 5s));
    run_for(300ms);
    EXPECT_TRUE(core->status().motion.has_value()) << "the motion goes on, as before";
    EXPECT_FALSE(ended());
}

// The happy path: braking before the limit.

TEST_F(Brake, ASpeedTowardsALimitStopsThatAxisWhileTheOtherKeepsMoving) {
    start_limited(-60, 20);
    ASSERT_TRUE(core->speed(alice, {0, 3000, 2000}, 30000ms).ok());
    ASSERT_TRUE(run_until([&] { return event_with(EndReason::kLimit).has_value(); }, 5s));
    const auto braked = *event_with(EndReason::kLimit);
    EXPECT_EQ(braked.change, MotionChange::kUpdated);
    EXPECT_EQ(braked.braked, std::vector<std::string>{"pitch"});
    EXPECT_EQ(braked.speed, (protocol::Axes{0, 0, 2000})) << "the speed now sent";
    const auto yaw_then = hall().yaw;
    run_for(400ms);
    // Stopped short of the limit, within the braking distance of it.
    EXPECT_LE(hall().pitch, 20.0);
    EXPECT_GE(hall().pitch, 20.0 - distance(30)) << "braked earlier than the distance";
    EXPECT_GT(hall().yaw, yaw_then + 2.0) << "yaw keeps moving";
    ASSERT_TRUE(core->status().motion.has_value());
    EXPECT_EQ(core->status().motion->speed, (protocol::Axes{0, 0, 2000}));
    const auto frames = speed_frames();
    EXPECT_NE(std::ranges::find(frames, Json::array({0, 0, 2000})), frames.end());
}

TEST_F(Brake, WhenNoAxisIsLeftMovingTheMotionEndsAtTheLimit) {
    start_limited(-20, 60);
    ASSERT_TRUE(core->speed(alice, {0, -4000, 0}, 30000ms).ok());
    ASSERT_TRUE(run_until([&] { return ended(); }, 5s));
    const auto& last = recorder.motions.back();
    EXPECT_EQ(last.reason, EndReason::kLimit);
    EXPECT_EQ(last.braked, std::vector<std::string>{"pitch"});
    ASSERT_TRUE(run_until([&] { return zero_speed_frames() >= 1; }));
    run_for(300ms);
    EXPECT_GE(hall().pitch, -20.0);
    EXPECT_LE(hall().pitch, -20.0 + distance(40));
    EXPECT_FALSE(core->status().motion.has_value());
}

// The owner's update that asks again for a braked axis keeps it at zero.
TEST_F(Brake, AnUpdateCannotUnbrakeAnAxisAtItsLimit) {
    start_limited(-60, 10);
    ASSERT_TRUE(core->speed(alice, {0, 2000, 1000}, 30000ms).ok());
    ASSERT_TRUE(run_until([&] { return event_with(EndReason::kLimit).has_value(); }, 5s));
    const auto limit_events = [&] {
        return std::ranges::count_if(
            recorder.motions, [](const MotionEvent& e) { return e.reason == EndReason::kLimit; });
    };
    for (int i = 0; i < 5; ++i) {
        const auto again = core->speed(alice, {0, 2000, 1000}, 30000ms);
        ASSERT_TRUE(again.ok());
        EXPECT_EQ(again->speed, (protocol::Axes{0, 0, 1000}));
        EXPECT_EQ(again->braked, std::vector<std::string>{"pitch"});
        run_for(50ms);
    }
    EXPECT_EQ(limit_events(), 1) << "the same braked axis is not news";
    EXPECT_LE(hall().pitch, 10.0);
}

// A joystick streaming towards the limit: its own updates are braked as
// they arrive, published once at once (reason limit), never past the limit.
TEST_F(Brake, AStreamingOwnersUpdatesAreBrakedAsTheyArrive) {
    start_limited(-60, 8);
    std::size_t braked_replies = 0;
    for (int i = 0; i < 40; ++i) {  // 20 Hz for 2 s at 10 °/s: 20° wanted
        const auto r = core->speed(alice, {0, 1000, 500}, 30000ms, false, 300ms);
        ASSERT_TRUE(r.ok()) << r.error().message;
        braked_replies += r->braked.empty() ? 0 : 1;
        run_for(50ms);
    }
    EXPECT_GT(braked_replies, 0U);
    EXPECT_LE(hall().pitch, 8.0);
    EXPECT_GE(hall().pitch, 8.0 - distance(10));
    EXPECT_GT(hall().yaw, 5.0) << "yaw went on";
    const auto limit_events = std::ranges::count_if(
        recorder.motions, [](const MotionEvent& e) { return e.reason == EndReason::kLimit; });
    EXPECT_EQ(limit_events, 1);
    EXPECT_EQ(std::ranges::count_if(
                  recorder.motions,
                  [](const MotionEvent& e) { return e.change == MotionChange::kStarted; }),
              1);
    ASSERT_TRUE(core->status().motion.has_value());
    EXPECT_EQ(core->status().motion->speed, (protocol::Axes{0, 0, 500}));
}

// A reload that narrows a limit brakes the motion already running.
TEST_F(Brake, AReloadNarrowingALimitBrakesTheRunningMotion) {
    start_limited(-60, 60);
    ASSERT_TRUE(core->speed(alice, {0, 2000, 0}, 30000ms).ok());
    ASSERT_TRUE(run_until([&] { return hall().pitch > 8.0; }, 5s));
    auto next = test_config(simulator->device_path());
    next.limits.pitch = {-60, 5};
    core->reload(next);
    ASSERT_TRUE(run_until([&] { return ended(); }, 2s));
    EXPECT_EQ(recorder.motions.back().reason, EndReason::kLimit);
}

// Status of a speed motion: the lease shortens time_left; elapsed counts up.
TEST_F(Brake, StatusTimeLeftCountsTheLeaseAndElapsedCountsUp) {
    start_limited(-60, 60);
    ASSERT_TRUE(core->speed(alice, {0, 0, 500}, 30000ms, false, 2000ms).ok());
    run_for(200ms);
    const auto motion = core->status().motion;
    ASSERT_TRUE(motion.has_value());
    EXPECT_LE(motion->time_left, 2000ms) << "ends with its lease, long before its duration";
    EXPECT_GE(motion->time_left, 1000ms);
    EXPECT_GE(motion->elapsed, 150ms);
    EXPECT_LE(motion->elapsed, 2000ms);
}

}  // namespace
}  // namespace gport::testing
