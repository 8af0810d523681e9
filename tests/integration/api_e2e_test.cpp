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

}  // namespace
}  // namespace gport::testing
