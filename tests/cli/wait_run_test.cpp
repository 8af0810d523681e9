// gportctl as a health check (issue 32): status exits 75 while the link is
// not up; wait link blocks until it is, on the link topic, or gives up.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sstream>

#include "gport/cli/run.hpp"
#include "server_harness.hpp"

namespace gport::cli {
namespace {

using nlohmann::json;
using ::testing::HasSubstr;
using testing::ServerHarness;

struct WaitRan {
    int status;
    std::string out;
    std::string err;
};

class WaitTest : public ::testing::Test {
  protected:
    WaitRan run(
        std::vector<std::string> args, std::function<bool()> interrupted = [] { return false; }) {
        args.insert(args.begin(), {"--socket", h_.path()});
        std::ostringstream out;
        std::ostringstream err;
        const int status = main_with(args, nullptr, out, err, std::move(interrupted));
        return {status, out.str(), err.str()};
    }

    void set_link(daemon::LinkState state) {
        h_.on_io([&] { h_.api.status_value.link = state; });
    }

    ServerHarness h_;
};

TEST_F(WaitTest, StatusExits75WhileTheLinkIsDownButPrintsAsEver) {
    set_link(daemon::LinkState::kDown);
    const auto human = run({"status"});
    EXPECT_EQ(human.status, kExitLinkNotUp);
    EXPECT_EQ(kExitLinkNotUp, 75);
    EXPECT_THAT(human.out, HasSubstr("link:      down"));
    EXPECT_EQ(human.err, "");
    const auto script = run({"--json", "status"});
    EXPECT_EQ(script.status, kExitLinkNotUp);
    EXPECT_EQ(json::parse(script.out)["link"]["state"], "down");
}

TEST_F(WaitTest, StatusExits75WhileTheLinkIsStale) {
    set_link(daemon::LinkState::kStale);
    EXPECT_EQ(run({"status"}).status, kExitLinkNotUp);
}

TEST_F(WaitTest, StatusExits0WhenTheLinkIsUp) {
    set_link(daemon::LinkState::kUp);
    EXPECT_EQ(run({"status"}).status, kExitOk);
}

TEST_F(WaitTest, UsageErrorsBeforeAnyConnection) {
    for (const auto& args :
         std::vector<std::vector<std::string>>{{"wait"},
                                               {"wait", "disk"},
                                               {"wait", "link", "--timeout", "soon"},
                                               {"wait", "link", "--timeout", "2d"},
                                               {"wait", "link", "--for", "1s"}}) {
        const auto ran = run(args);
        EXPECT_EQ(ran.status, kExitUsage) << args.back();
        EXPECT_THAT(ran.err, HasSubstr("Try 'gportctl wait --help'.")) << ran.err;
    }
    EXPECT_THAT(run({"wait", "disk"}).err, HasSubstr("link"));
    EXPECT_TRUE(h_.on_io([&] { return h_.api.calls.empty() && h_.api.status_calls == 0; }));
}

TEST_F(WaitTest, UnreachableDaemonIs69) {
    std::ostringstream out;
    std::ostringstream err;
    EXPECT_EQ(main_with({"--socket", h_.dir() + "/none.sock", "wait", "link"}, nullptr, out, err,
                        [] { return false; }),
              kExitUnavailable);
}

TEST_F(WaitTest, TimesOutWith75NamingWhatItWaitedFor) {
    set_link(daemon::LinkState::kDown);
    h_.on_io([&] { h_.api.status_value.link_reason = "cannot open /dev/gimbal"; });
    const auto start = std::chrono::steady_clock::now();
    const auto ran = run({"wait", "link", "--timeout", "300ms"});
    EXPECT_GE(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(300));
    EXPECT_EQ(ran.status, kExitLinkNotUp);
    EXPECT_EQ(ran.out, "");
    EXPECT_EQ(ran.err,
              "gportctl: wait link: the link is not up after 300 ms "
              "(link: down (cannot open /dev/gimbal))\n");
}

TEST_F(WaitTest, InterruptedExits130) {
    set_link(daemon::LinkState::kDown);
    int polls = 0;
    EXPECT_EQ(run({"wait", "link"}, [&] { return ++polls > 3; }).status, kExitInterrupted);
}

TEST_F(WaitTest, UpAlreadyExits0AtOnce) {
    set_link(daemon::LinkState::kUp);
    const auto ran = run({"wait", "link", "--timeout", "10s"});
    EXPECT_EQ(ran.status, kExitOk) << ran.err;
    EXPECT_THAT(ran.out, ::testing::StartsWith("link: up"));
    const auto script = run({"--json", "wait", "link"});
    EXPECT_EQ(json::parse(script.out)["state"], "up");
}

// The link comes up while gportctl waits: the link event ends the wait,
// without another status call (no polling).
TEST_F(WaitTest, ALinkEventEndsTheWait) {
    set_link(daemon::LinkState::kDown);
    bool published = false;
    const auto ran = run({"wait", "link", "--timeout", "10s"}, [&] {
        if (!published && h_.on_io([&] { return h_.api.status_calls > 0; })) {
            published = true;
            h_.on_io([&] {
                h_.api.emit_link({daemon::LinkState::kStale, "no attitude for 500 ms"});
                h_.api.emit_link({daemon::LinkState::kUp, "attitude arriving"});
            });
        }
        return false;
    });
    EXPECT_EQ(ran.status, kExitOk) << ran.err;
    EXPECT_EQ(ran.out, "link: up (attitude arriving)\n");
    EXPECT_EQ(h_.on_io([&] { return h_.api.status_calls; }), 1u);
}

}  // namespace
}  // namespace gport::cli
