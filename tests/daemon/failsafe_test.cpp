// Failsafe on commander loss: what reaches the gimbal when a speed motion
// ends because its owner went away or the daemon shuts down. Whatever the
// policy, zero speed goes first and the motion ends with its reason.
#include "core_fixture.hpp"

namespace gport::testing {
namespace {

using config::Failsafe;
using daemon::EndReason;
using daemon::MotionChange;

class FailsafeTest : public CoreFixture {
  protected:
    void start_with(Failsafe on_owner_gone, Failsafe on_shutdown) {
        start({}, [&](config::Config& c) {
            c.failsafe.on_owner_gone = on_owner_gone;
            c.failsafe.on_shutdown = on_shutdown;
        });
        ASSERT_TRUE(run_until([&] { return link_up() && !recorder.attitude.empty(); }));
        auto started = core->speed(alice, {0, 1000, 2000}, 30000ms);
        ASSERT_TRUE(started.ok()) << started.error().message;
        run_for(200ms);
    }

    // The hall angles the core holds as its latest sample, as [r, p, y].
    Json latest_hall() const {
        const auto hall = core->latest_attitude()->attitude.hall;
        return Json::array({hall.roll, hall.pitch, hall.yaw});
    }

    // Index in the trace of the first 0x85 frame with `mode` after `from`.
    std::optional<std::size_t> first_control(const std::string& mode, std::size_t from = 0) const {
        for (std::size_t i = from; i < trace.size(); ++i) {
            if (trace[i].value("cmd", "") == "0x85" && trace[i].value("mode", "") == mode) {
                return i;
            }
        }
        return std::nullopt;
    }

    std::optional<std::size_t> first_zero_speed() const {
        for (std::size_t i = 0; i < trace.size(); ++i) {
            if (trace[i].value("cmd", "") == "0x85" && trace[i].value("mode", "") == "speed" &&
                trace[i]["speed"] == Json::array({0, 0, 0})) {
                return i;
            }
        }
        return std::nullopt;
    }

    void shut_down() {
        bool done = false;
        core->shutdown([&] { done = true; });
        ASSERT_TRUE(run_until([&] { return done; }, 5s));
        core.reset();
        run_for(200ms);  // the simulator reads what was written
    }

    void expect_ended(EndReason reason) {
        ASSERT_FALSE(recorder.motions.empty());
        EXPECT_EQ(recorder.motions.back().change, MotionChange::kEnded);
        EXPECT_EQ(recorder.motions.back().reason, reason);
    }
};

TEST_F(FailsafeTest, OwnerGoneStopSendsOnlyZeroSpeed) {
    start_with(Failsafe::kStop, Failsafe::kStop);
    core->client_gone(alice);
    ASSERT_TRUE(run_until([&] { return zero_speed_frames() == 1; }, 5s));
    run_for(200ms);
    expect_ended(EndReason::kOwnerGone);
    EXPECT_FALSE(first_control("angle"));
    EXPECT_FALSE(first_control("center"));
}

TEST_F(FailsafeTest, OwnerGoneHoldSendsZeroSpeedThenTheLatestHallAngles) {
    start_with(Failsafe::kHold, Failsafe::kStop);
    const auto hall = latest_hall();  // no loop turn before client_gone
    core->client_gone(alice);
    ASSERT_TRUE(run_until([&] { return first_control("angle").has_value(); }, 5s));
    expect_ended(EndReason::kOwnerGone);
    const auto zero = first_zero_speed();
    ASSERT_TRUE(zero);
    const auto angle = first_control("angle");
    EXPECT_LT(*zero, *angle);
    EXPECT_EQ(trace[*angle]["angle"], hall);
}

TEST_F(FailsafeTest, OwnerGoneCenterSendsZeroSpeedThenCentre) {
    start_with(Failsafe::kCenter, Failsafe::kStop);
    core->client_gone(alice);
    ASSERT_TRUE(run_until([&] { return first_control("center").has_value(); }, 5s));
    expect_ended(EndReason::kOwnerGone);
    const auto zero = first_zero_speed();
    ASSERT_TRUE(zero);
    EXPECT_LT(*zero, *first_control("center"));
    EXPECT_FALSE(first_control("angle"));
}

TEST_F(FailsafeTest, ShutdownStopSendsOnlyZeroSpeed) {
    start_with(Failsafe::kCenter, Failsafe::kStop);
    shut_down();
    expect_ended(EndReason::kShutdown);
    EXPECT_EQ(zero_speed_frames(), 1U);
    EXPECT_FALSE(first_control("center"));
    EXPECT_FALSE(first_control("angle"));
}

TEST_F(FailsafeTest, ShutdownHoldSendsZeroSpeedThenTheLatestHallAngles) {
    start_with(Failsafe::kStop, Failsafe::kHold);
    const auto hall = latest_hall();
    shut_down();
    expect_ended(EndReason::kShutdown);
    const auto zero = first_zero_speed();
    const auto angle = first_control("angle");
    ASSERT_TRUE(zero);
    ASSERT_TRUE(angle);
    EXPECT_LT(*zero, *angle);
    EXPECT_EQ(trace[*angle]["angle"], hall);
}

TEST_F(FailsafeTest, ShutdownCenterSendsZeroSpeedThenCentre) {
    start_with(Failsafe::kStop, Failsafe::kCenter);
    shut_down();
    expect_ended(EndReason::kShutdown);
    const auto zero = first_zero_speed();
    const auto center = first_control("center");
    ASSERT_TRUE(zero);
    ASSERT_TRUE(center);
    EXPECT_LT(*zero, *center);
}

// Telemetry off: no attitude ever, so hold has nothing to hold and falls
// back to stop; the motion still ends.
TEST_F(FailsafeTest, HoldWithoutAttitudeFallsBackToStop) {
    sim::SimOptions options;
    options.model.stream_rate_hz = 0;
    start(options, [](config::Config& c) { c.failsafe.on_owner_gone = Failsafe::kHold; });
    ASSERT_TRUE(run_until([&] { return core->status().device_open; }));
    ASSERT_TRUE(core->speed(alice, {0, 0, 500}, 30000ms).ok());
    core->client_gone(alice);
    ASSERT_TRUE(run_until([&] { return zero_speed_frames() == 1; }, 5s));
    run_for(200ms);
    expect_ended(EndReason::kOwnerGone);
    EXPECT_FALSE(first_control("angle"));
}

// A reload changes the policy for a motion already running.
TEST_F(FailsafeTest, ReloadAppliesTheNewPolicy) {
    start_with(Failsafe::kStop, Failsafe::kStop);
    auto next = test_config(simulator->device_path());
    next.failsafe.on_owner_gone = Failsafe::kCenter;
    core->reload(next);
    core->client_gone(alice);
    ASSERT_TRUE(run_until([&] { return first_control("center").has_value(); }, 5s));
    expect_ended(EndReason::kOwnerGone);
}

// A lease that runs out is an owner gone as far as the gimbal cares: the
// on_owner_gone policy applies, and the motion ends lease_expired.
TEST_F(FailsafeTest, LeaseExpiryAppliesTheOwnerGonePolicy) {
    start({}, [](config::Config& c) { c.failsafe.on_owner_gone = Failsafe::kCenter; });
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    ASSERT_TRUE(core->speed(alice, {0, 0, 800}, 30000ms, false, 300ms).ok());
    ASSERT_TRUE(run_until([&] { return first_control("center").has_value(); }, 5s));
    expect_ended(EndReason::kLeaseExpired);
    const auto zero = first_zero_speed();
    ASSERT_TRUE(zero);
    EXPECT_LT(*zero, *first_control("center"));
}

// on_link_lost "center" when the attitude goes stale while a soft limit
// needs it (no_attitude): the device is open, so zero speed then centre.
TEST_F(FailsafeTest, LinkLostCenterOnAStaleAttitudeSendsZeroSpeedThenCentre) {
    sim::SimOptions options;
    options.faults.silence_every = 1500ms;
    options.faults.silence_for = 3000ms;
    start(options, [](config::Config& c) {
        c.failsafe.on_link_lost = Failsafe::kCenter;
        c.limits.pitch = {-80, 80};
    });
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    ASSERT_TRUE(run_until([&] { return core->speed(alice, {0, 300, 0}, 30000ms).ok(); }));
    ASSERT_TRUE(run_until([&] { return first_control("center").has_value(); }, 5s));
    expect_ended(EndReason::kNoAttitude);
    const auto zero = first_zero_speed();
    ASSERT_TRUE(zero);
    EXPECT_LT(*zero, *first_control("center"));
}

// on_link_lost "center" when the device itself goes away (link_down): there
// is nothing to send the centre frame to, and a position command is never
// replayed on reopen; only the owed zero speed goes out when it comes back.
TEST_F(FailsafeTest, LinkLostCenterOnAClosedDeviceSendsOnlyTheOwedZeroSpeed) {
    sim::SimOptions options;
    options.link_path =
        ::testing::TempDir() + "gport-failsafe-vanish-" + std::to_string(::getpid());
    options.faults.vanish_every = 800ms;
    options.faults.vanish_for = 300ms;
    start(options, [](config::Config& c) { c.failsafe.on_link_lost = Failsafe::kCenter; });
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    ASSERT_TRUE(run_until([&] { return core->speed(alice, {0, 0, 500}, 30000ms).ok(); }));
    ASSERT_TRUE(run_until([&] { return core->status().link == daemon::LinkState::kDown; }));
    expect_ended(EndReason::kLinkDown);
    const auto opens = core->status().counters.device_opens;
    ASSERT_TRUE(run_until([&] { return core->status().counters.device_opens > opens; }));
    run_for(300ms);
    EXPECT_FALSE(first_control("center")) << "no device to centre";
}

TEST_F(FailsafeTest, NoMotionNoFailsafe) {
    start({}, [](config::Config& c) { c.failsafe.on_owner_gone = Failsafe::kCenter; });
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    core->client_gone(alice);
    run_for(200ms);
    EXPECT_FALSE(first_control("center"));
    EXPECT_EQ(zero_speed_frames(), 0U);
}

}  // namespace
}  // namespace gport::testing
