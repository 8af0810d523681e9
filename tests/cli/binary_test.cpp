// The gportctl executable itself: exit statuses, and SIGINT during a speed.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include "server_harness.hpp"

extern char** environ;

namespace {

using gport::testing::ServerHarness;

pid_t spawn(std::vector<std::string> args) {
    args.insert(args.begin(), GPORTCTL_PATH);
    std::vector<char*> argv;
    for (auto& a : args) {
        argv.push_back(a.data());
    }
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
    pid_t pid = -1;
    EXPECT_EQ(posix_spawn(&pid, GPORTCTL_PATH, &actions, nullptr, argv.data(), environ), 0);
    posix_spawn_file_actions_destroy(&actions);
    return pid;
}

int exit_status(pid_t pid) {
    int status = 0;
    EXPECT_EQ(::waitpid(pid, &status, 0), pid);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

TEST(Gportctl, ExitStatuses) {
    EXPECT_EQ(exit_status(spawn({"--help"})), 0);
    EXPECT_EQ(exit_status(spawn({"fly"})), 64);
    EXPECT_EQ(exit_status(spawn({"speed", "--yaw", "1000"})), 64);
    EXPECT_EQ(exit_status(spawn({"--version"})), 0);
    EXPECT_EQ(exit_status(spawn({"status", "--verbose"})), 64);
    EXPECT_EQ(exit_status(spawn({"speed", "--for", "2d"})), 64);
    EXPECT_EQ(exit_status(spawn({"watch", "-n", "-1"})), 64);
    EXPECT_EQ(exit_status(spawn({"--socket", "/nonexistent/gportd.sock", "status"})), 69);
    ServerHarness h;
    EXPECT_EQ(exit_status(spawn({"--socket", h.path(), "center"})), 0);
    h.on_io([&] {
        h.api.error = gport::daemon::CommandError{gport::daemon::ErrorCode::kPermission, "no"};
    });
    EXPECT_EQ(exit_status(spawn({"--socket", h.path(), "center"})), 1);
}

TEST(Gportctl, SigintDuringSpeedSendsStopAndExitsZero) {
    ServerHarness h;
    const pid_t pid = spawn({"--socket", h.path(), "speed", "--yaw", "10"});
    ASSERT_TRUE(h.eventually([&] { return h.api.calls.size() >= 2; }));
    ::kill(pid, SIGINT);
    EXPECT_EQ(exit_status(pid), 0);
    EXPECT_THAT(h.on_io([&] { return h.api.calls.back(); }), ::testing::HasSubstr("stop"));
}

}  // namespace
