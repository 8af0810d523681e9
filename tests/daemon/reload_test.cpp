// SIGHUP's part in the core: Core::reload() applies the access lists (with a
// fresh per-connection cache) and the speed durations without touching a
// running motion; plan_reload() sorts changed keys into applied and
// needing a restart.
#include "../../daemon/src/reload.hpp"

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

TEST(PlanReload, SortsChangedKeysIntoAppliedAndNeedingARestart) {
    config::Config running;
    config::Config next;
    next.log.level = "debug";
    next.access.control_gids = {27};
    next.keepalive.max_duration = 5000ms;
    next.serial.baud = 9600;
    next.socket.max_clients = 8;
    const auto plan = daemon::plan_reload(running, next);
    EXPECT_EQ(plan.applied, (std::vector<std::string>{"keepalive.max_duration_ms",
                                                      "access.control_gids", "log.level"}));
    EXPECT_EQ(plan.need_restart, (std::vector<std::string>{"serial.baud", "socket.max_clients"}));
    EXPECT_EQ(plan.in_effect.log.level, "debug");
    EXPECT_EQ(plan.in_effect.serial.baud, running.serial.baud) << "kept until a restart";
}

TEST(PlanReload, NothingChangedMeansNothingToDo) {
    const auto plan = daemon::plan_reload(config::Config{}, config::Config{});
    EXPECT_TRUE(plan.applied.empty());
    EXPECT_TRUE(plan.need_restart.empty());
}

}  // namespace
}  // namespace gport::testing
