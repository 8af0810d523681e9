// SIGHUP's part in the core: Core::reload() applies the access lists (with a
// fresh per-connection cache) and the speed durations without touching a
// running motion. (Which keys a reload applies is the app's: tests/app.)
#include <gtest/gtest.h>

#include "core_fixture.hpp"

namespace gport::testing {
namespace {

using daemon::ErrorCode;

TEST_F(CoreFixture, ReloadRebuildsTheAccessPolicyAndForgetsCachedDecisions) {
    auto cfg = test_config("/dev/unused");
    start({}, [](config::Config& c) { c.access.control_uids = {4242}; });
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    EXPECT_FALSE(core->may_command(bob));  // now cached for bob's connection
    cfg.access.control_uids = {bob.uid};
    core->reload(cfg);
    EXPECT_TRUE(core->may_command(bob));
    EXPECT_TRUE(core->center(bob).ok());
    cfg.access.control_uids = {4242};
    core->reload(cfg);
    auto r = core->center(bob);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::kPermission);
}

TEST_F(CoreFixture, ReloadChangesSpeedDurationsButNotTheRunningMotion) {
    auto cfg = test_config("/dev/unused");
    start();
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    ASSERT_TRUE(core->speed(alice, {0, 0, 500}, 30000ms).ok());
    cfg.keepalive.max_duration = 2000ms;
    cfg.keepalive.default_duration = 1500ms;
    core->reload(cfg);
    const auto refused = core->speed(alice, {0, 0, 500}, 5000ms);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, ErrorCode::kInvalidParams);
    ASSERT_TRUE(core->status().motion.has_value());
    EXPECT_GT(core->status().motion->time_left, 20000ms) << "the running motion was cut short";
    EXPECT_EQ(zero_speed_frames(), 0u);
}

TEST_F(CoreFixture, ReloadAppliesTheSoftLimitsToTheNextCommand) {
    auto cfg = test_config("/dev/unused");
    start();
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    ASSERT_TRUE(core->angle(alice, {0, -10000, 0}).ok()) << "no limits by default";
    cfg.limits.pitch = {-90.0, 30.0};
    cfg.limits.max_speed = 50.0;
    core->reload(cfg);
    const auto refused = core->angle(alice, {0, -10000, 0});
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, ErrorCode::kInvalidParams);
    EXPECT_NE(refused.error().message.find("limits.pitch"), std::string::npos);
    const auto clamped = core->angle(alice, {0, -10000, 0}, true);
    ASSERT_TRUE(clamped.ok());
    EXPECT_EQ(clamped->angle, (protocol::Axes{0, -9000, 0}));
    EXPECT_FALSE(core->speed(alice, {0, 0, 6000}, 1000ms).ok());
    const auto fast = core->speed(alice, {0, 0, -6000}, 1000ms, true);
    ASSERT_TRUE(fast.ok());
    EXPECT_EQ(fast->speed, (protocol::Axes{0, 0, -5000}));
    ASSERT_TRUE(run_until([&] {
        const auto frames = speed_frames();
        return !frames.empty() && frames.back() == Json::array({0, 0, -5000});
    }));
}

}  // namespace
}  // namespace gport::testing
