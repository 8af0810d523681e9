// The client API end to end: the real gportd with its simulated gimbal
// (--simulate), every method, many clients, a slow reader, and gportctl.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <memory>
#include <thread>

#include "harness.hpp"

namespace gport::testing {
namespace {

using ::testing::HasSubstr;

class ApiEndToEnd : public ::testing::Test {
  protected:
    void SetUp() override {
        daemon_ = std::make_unique<DaemonProcess>(dir_, std::vector<std::string>{"--simulate"});
        client_ = std::make_unique<Client>(daemon_->socket());
        ASSERT_TRUE(client_->connected());
        ASSERT_TRUE(link_up(*client_));
    }

    int gportctl(std::vector<std::string> args) {
        args.insert(args.begin(), {GPORTCTL_PATH, "--socket", daemon_->socket()});
        Process process(args);
        return process.wait(20s).value_or(-1);
    }

    // gportctl's exit status and its stdout and stderr, merged, as lines.
    std::pair<int, std::vector<std::string>> gportctl_says(std::vector<std::string> args) {
        args.insert(args.begin(), {"/bin/sh", "-c", "exec \"$0\" \"$@\" 2>&1", GPORTCTL_PATH,
                                   "--socket", daemon_->socket()});
        Process process(args);
        const int status = process.wait(20s).value_or(-1);
        std::vector<std::string> lines;
        while (auto line = process.next_line(5s)) {
            lines.push_back(*line);
        }
        return {status, lines};
    }

    TempDir dir_;
    std::unique_ptr<DaemonProcess> daemon_;
    std::unique_ptr<Client> client_;
};

TEST_F(ApiEndToEnd, EveryMethodAnswersAsDocumented) {
    auto& c = *client_;
    auto status = c.call("status")["result"];
    EXPECT_EQ(status["clients"], 1);
    EXPECT_TRUE(status["device_open"].get<bool>());
    EXPECT_GT(status["counters"]["attitude_frames"].get<int>(), 0);
    EXPECT_EQ(status["client"]["pid"], static_cast<int>(::getpid()));
    // The file it loaded (the harness's), for set-up tools (gport-web).
    EXPECT_EQ(status["config_file"], dir_.file("gportd.json"));

    auto attitude = c.call("attitude")["result"];
    EXPECT_GT(attitude["seq"].get<int>(), 0);
    EXPECT_TRUE(attitude["imu"].contains("yaw"));
    EXPECT_GE(attitude["age_ms"].get<int>(), 0);

    auto subscribed = c.call("subscribe", {{"topics", {"attitude", "motion"}}})["result"];
    EXPECT_EQ(subscribed["topics"], Json({"attitude", "motion"}));
    ASSERT_TRUE(c.notification("attitude").has_value());

    auto speed = c.call("speed", {{"yaw", 15}, {"duration_ms", 2000}})["result"];
    EXPECT_EQ(speed["duration_ms"], 2000);
    EXPECT_GT(speed["ends_at"].get<double>(), 1.6e9);
    auto started = c.notification("motion");
    ASSERT_TRUE(started.has_value());
    EXPECT_EQ((*started)["params"]["change"], "started");
    EXPECT_EQ(c.call("stop")["result"]["sent"], true);
    for (const auto* method : {"center", "lock", "photo", "record"}) {
        EXPECT_EQ(c.call(method)["result"]["sent"], true) << method;
    }
    EXPECT_EQ(c.call("angle", {{"pitch", -30}})["result"]["sent"], true);

    EXPECT_EQ(c.call("acquire")["result"]["you_hold_control"], true);
    Client other(daemon_->socket());
    auto busy = other.call("photo");
    EXPECT_EQ(busy["error"]["code"], -32003);
    EXPECT_THAT(busy["error"]["message"].get<std::string>(), HasSubstr(std::to_string(::getpid())));
    EXPECT_TRUE(c.call("release")["result"]["controller"].is_null());
    EXPECT_EQ(other.call("photo")["result"]["sent"], true);

    auto settings = c.call("set_settings", {{"dead_zone", 7}})["result"];
    EXPECT_EQ(settings["dead_zone"], 7);
    EXPECT_EQ(c.call("get_settings")["result"]["dead_zone"], 7);

    EXPECT_EQ(c.call("unsubscribe")["result"]["topics"], Json::array());
    EXPECT_EQ(c.call("angle", {{"roll", 500}})["error"]["code"], -32602);
    EXPECT_EQ(c.call("fly")["error"]["code"], -32601);
}

TEST_F(ApiEndToEnd, ManyClientsEachGetTheStream) {
    constexpr int kClients = 40;
    std::vector<std::unique_ptr<Client>> clients;
    for (int i = 0; i < kClients; ++i) {
        clients.push_back(std::make_unique<Client>(daemon_->socket()));
        ASSERT_EQ(clients.back()->call("subscribe", {{"topics", {"attitude"}}})["result"]["topics"],
                  Json({"attitude"}));
    }
    EXPECT_EQ(client_->call("status")["result"]["clients"], kClients + 1);
    for (auto& c : clients) {
        long last = 0;
        for (int i = 0; i < 5; ++i) {
            auto sample = c->notification("attitude");
            ASSERT_TRUE(sample.has_value());
            const long seq = (*sample)["params"]["seq"].get<long>();
            EXPECT_GT(seq, last) << "in order, no duplicates";
            last = seq;
        }
    }
}

TEST_F(ApiEndToEnd, SlowReaderStaysConnectedAndDelaysNobody) {
    Client slow(daemon_->socket());
    Client fast(daemon_->socket());
    slow.call("subscribe", {{"topics", {"attitude"}}});
    fast.call("subscribe", {{"topics", {"attitude"}}});
    // `slow` reads nothing for a while; `fast` keeps receiving meanwhile.
    int received = 0;
    const auto until = std::chrono::steady_clock::now() + 2s;
    while (std::chrono::steady_clock::now() < until) {
        if (fast.notification("attitude", 1s)) {
            ++received;
        }
    }
    EXPECT_GT(received, 10);
    auto status = slow.call("status", nullptr, 20s);
    ASSERT_TRUE(status.contains("result")) << "the slow reader was disconnected";
    EXPECT_EQ(status["result"]["clients"], 3);
}

TEST_F(ApiEndToEnd, GportctlTalksToTheDaemon) {
    EXPECT_EQ(gportctl({"status"}), 0);
    EXPECT_EQ(gportctl({"--json", "attitude"}), 0);
    EXPECT_EQ(gportctl({"speed", "--yaw", "5", "--for", "300ms"}), 0);
    EXPECT_EQ(gportctl({"settings", "--follow-speed", "9"}), 0);
    EXPECT_EQ(client_->call("get_settings")["result"]["follow_speed"], 9);
    EXPECT_EQ(gportctl({"angle", "--pitch", "400"}), 64);
    client_->call("acquire");
    EXPECT_EQ(gportctl({"photo"}), 1) << "another client holds control";
}

// Issue 26: call and limits reach the real daemon; its refusals are worded
// for the command line (but for `call`, which speaks the API); watch's
// header stays off a pipe.
TEST_F(ApiEndToEnd, GportctlCallLimitsAndRefusalsInItsOwnWords) {
    auto [called, result] = gportctl_says({"call", "limits"});
    EXPECT_EQ(called, 0);
    ASSERT_EQ(result.size(), 1U);
    EXPECT_EQ(Json::parse(result[0])["max_speed"], 327.67);
    auto [listed, limits] = gportctl_says({"limits"});
    EXPECT_EQ(listed, 0);
    EXPECT_THAT(limits, ::testing::Contains(HasSubstr("max speed:      327.67 deg/s")));
    // The recording state is unknown at start: on is refused.
    auto [refused, said] = gportctl_says({"record", "on"});
    EXPECT_EQ(refused, 1);
    ASSERT_EQ(said.size(), 1U);
    EXPECT_THAT(said[0], HasSubstr("gportctl: error -32602: the recording state is unknown"));
    EXPECT_THAT(said[0], HasSubstr("run 'gportctl record on --force' to toggle anyway"));
    auto [api, api_said] = gportctl_says({"call", "record", R"({"on": false})"});
    EXPECT_EQ(api, 1);
    ASSERT_EQ(api_said.size(), 1U);
    EXPECT_THAT(api_said[0], HasSubstr(R"(send record {"on": false, "force": true})"));
    auto [unknown, typo] = gportctl_says({"call", "stauts"});
    EXPECT_EQ(unknown, 1);
    EXPECT_THAT(typo, ::testing::Contains(HasSubstr("error -32601: unknown method")));
    auto [watched, events] = gportctl_says({"watch", "link", "--for", "300ms"});
    EXPECT_EQ(watched, 0);
    EXPECT_THAT(events, ::testing::Not(::testing::Contains(HasSubstr("watching"))));
}

}  // namespace
}  // namespace gport::testing
