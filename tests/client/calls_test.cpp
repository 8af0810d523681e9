// Every method of the blocking Client against gportd --simulate.
#include <unistd.h>

#include "client_fixture.hpp"

namespace gport::testing {
namespace {

using ClientCalls = SimulatedDaemonTest;

TEST_F(ClientCalls, StatusIsTyped) {
    const auto s = client().status();
    EXPECT_EQ(s.api_version, 1);
    EXPECT_FALSE(s.daemon_version.empty());
    EXPECT_EQ(s.link.state, "up");
    EXPECT_TRUE(s.device_open);
    EXPECT_GT(s.counters.attitude_frames, 0U);
    EXPECT_GT(s.counters.frames_in, 0U);
    EXPECT_TRUE(s.attitude_age_ms.has_value());
    EXPECT_GE(s.clients, 1);
    EXPECT_FALSE(s.motion.has_value());
    EXPECT_FALSE(s.controller.has_value());
    EXPECT_EQ(s.recording, "unknown");
    EXPECT_EQ(s.self.pid, ::getpid());
}

TEST_F(ClientCalls, AttitudeIsTheLatestSample) {
    const auto a = client().attitude();
    EXPECT_GT(a.seq, 0U);
    EXPECT_GT(a.time, 1.6e9) << "seconds since the epoch";
    ASSERT_TRUE(a.age_ms.has_value());
    EXPECT_GE(*a.age_ms, 0);
    EXPECT_GT(client().attitude().seq, 0U);
}

TEST_F(ClientCalls, SpeedStartsAMotionAndStopEndsIt) {
    const auto r = client().speed({.yaw = 20}, 5000ms, 2000ms);
    EXPECT_EQ(r.speed.yaw, 20);
    EXPECT_EQ(r.duration_ms, 5000);
    EXPECT_GT(r.ends_at, 1.6e9);
    EXPECT_TRUE(r.clamped.empty());
    const auto s = client().status();
    ASSERT_TRUE(s.motion.has_value());
    EXPECT_EQ(s.motion->mode, "speed");
    ASSERT_TRUE(s.motion->speed.has_value());
    EXPECT_EQ(s.motion->speed->yaw, 20);
    ASSERT_TRUE(s.motion->owner.has_value());
    EXPECT_EQ(s.motion->owner->pid, ::getpid());
    client().stop();
    EXPECT_FALSE(client().status().motion.has_value());
}

TEST_F(ClientCalls, SpeedClampFollowsTheSoftLimit) {
    daemon_.reset();
    client_.reset();
    start(R"("limits": {"max_speed": 50})");
    EXPECT_EQ(error_code_of([&] { client().speed({.yaw = 80}, 1000ms); }), -32602);
    const auto r = client().speed({.yaw = 80}, gc::SpeedOptions{1000ms, std::nullopt, true});
    EXPECT_EQ(r.speed.yaw, 50);
    EXPECT_EQ(r.clamped, std::vector<std::string>{"yaw"});
    client().stop();
}

TEST_F(ClientCalls, AngleCenterLockPhoto) {
    const auto a = client().angle({.pitch = -20, .yaw = 30});
    EXPECT_TRUE(a.sent);
    EXPECT_EQ(a.angle.pitch, -20);
    EXPECT_EQ(a.angle.yaw, 30);
    EXPECT_TRUE(a.clamped.empty());
    EXPECT_FALSE(a.ended.has_value()) << "no wait: no end";
    EXPECT_TRUE(client().center().sent);
    EXPECT_NO_THROW(client().lock());
    EXPECT_NO_THROW(client().photo());
    EXPECT_EQ(client().status().counters.frames_refused, 0U);
}

TEST_F(ClientCalls, AngleWaitReportsHowTheMotionEnded) {
    try {
        const auto a = client().angle({.yaw = 10}, {.wait = true});
        ASSERT_TRUE(a.ended.has_value());
        EXPECT_EQ(a.ended->reason, "reached");
        ASSERT_TRUE(a.ended->attitude.has_value());
        EXPECT_NEAR(a.ended->attitude->hall.yaw, 10, 1.0);
        const auto c = client().center({.wait = true});
        ASSERT_TRUE(c.ended.has_value());
        EXPECT_EQ(c.ended->reason, "reached");
    } catch (const gc::Error& e) {
        // Until the daemon has tracked motions (helper "track", issue 12
        // item 4) it refuses the unknown parameter; re-enabled at the merge.
        if (e.code() == -32602 && e.message().find("wait") != std::string::npos) {
            GTEST_SKIP() << "this gportd has no `wait` yet: " << e.what();
        }
        throw;
    }
}

TEST_F(ClientCalls, RecordToggleAndAssumedState) {
    EXPECT_EQ(client().record().recording, "unknown") << "a toggle from unknown stays unknown";
    EXPECT_EQ(error_code_of([&] { client().record(true); }), -32602) << "unknown needs force";
    const auto forced = client().record(true, true);
    EXPECT_TRUE(forced.sent);
    EXPECT_EQ(forced.recording, "on");
    const auto again = client().record(true);
    EXPECT_FALSE(again.sent) << "already on";
    EXPECT_EQ(client().record(false).recording, "off");
}

TEST_F(ClientCalls, AcquireAndRelease) {
    const auto held = client().acquire();
    EXPECT_TRUE(held.you_hold_control);
    ASSERT_TRUE(held.controller.has_value());
    EXPECT_EQ(held.controller->pid, ::getpid());
    EXPECT_TRUE(client().status().controller.has_value());
    const auto released = client().release();
    EXPECT_FALSE(released.you_hold_control);
    EXPECT_FALSE(released.controller.has_value());
}

TEST_F(ClientCalls, SettingsReadAndChange) {
    const auto before = client().settings();
    const int wanted = before.dead_zone == 4 ? 5 : 4;
    const auto after = client().set_settings({.dead_zone = wanted});
    EXPECT_EQ(after.dead_zone, wanted);
    EXPECT_EQ(after.follow_speed, before.follow_speed) << "only the given field changes";
    EXPECT_EQ(client().settings().dead_zone, wanted);
    EXPECT_EQ(error_code_of([&] { client().set_settings({}); }), -32602);
}

TEST_F(ClientCalls, LimitsAreTheConfiguredOnes) {
    const auto l = client().limits();  // the fixture's config sets none: the protocol's range
    EXPECT_EQ(l.pitch.min, -327.67);
    EXPECT_EQ(l.pitch.max, 327.67);
    EXPECT_EQ(l.yaw.max, 327.67);
    EXPECT_EQ(l.max_speed, 327.67);
    EXPECT_EQ(l.braking_margin_deg, 1.0);
}

TEST_F(ClientCalls, DefaultSocketComesFromTheEnvironment) {
    ::setenv("GPORT_SOCKET", socket().c_str(), 1);
    EXPECT_EQ(gc::Client::default_socket(), socket());
    EXPECT_EQ(gc::Client::connect().status().link.state, "up");
    ::setenv("GPORT_SOCKET", "", 1);
    EXPECT_EQ(gc::Client::default_socket(), "/run/gportd.sock");
    ::unsetenv("GPORT_SOCKET");
}

}  // namespace
}  // namespace gport::testing
