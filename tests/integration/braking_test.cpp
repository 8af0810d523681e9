// Issue 12, item 1b end to end: the real gportd brakes a speed motion at
// its soft limits by the attitude of the real gport-sim, whose mechanical
// limits (--limits) lie beyond the soft ones, so a gimbal that stops short
// of the soft limit was stopped by gportd. Also: a speed outwards from
// beyond a limit is zeroed; a stale link ends the motion (no_attitude); a
// hung streaming client is stopped by its lease, and the failsafe applies.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "harness.hpp"

namespace gport::testing {
namespace {

Json trace_line(const std::string& line) {
    return Json::parse(line, nullptr, false);
}

bool is_control(const Json& j, const std::string& mode) {
    return j.is_object() && j.value("cmd", "") == "0x85" && j.value("mode", "") == mode;
}

class Braking : public ::testing::Test {
  protected:
    void start(const std::vector<std::string>& sim_args, const std::string& config) {
        sim_ = std::make_unique<SimProcess>(dir_, sim_args);
        daemon_ = std::make_unique<DaemonProcess>(
            dir_, std::vector<std::string>{"--device", sim_->link()}, std::vector<std::string>{},
            config);
        client_ = std::make_unique<Client>(daemon_->socket());
        ASSERT_TRUE(client_->connected());
        ASSERT_TRUE(link_up(*client_));
        ASSERT_TRUE(client_->call("subscribe", {{"topics", {"motion"}}}).contains("result"));
    }

    // The next motion notification whose params satisfy pred.
    std::optional<Json> motion_where(const std::function<bool(const Json&)>& pred) {
        while (auto n = client_->notification("motion")) {
            if (pred((*n)["params"])) {
                return (*n)["params"];
            }
        }
        return std::nullopt;
    }

    Json hall() { return client_->call("attitude")["result"]["hall"]; }

    TempDir dir_;
    std::unique_ptr<SimProcess> sim_;
    std::unique_ptr<DaemonProcess> daemon_;
    std::unique_ptr<Client> client_;
};

TEST_F(Braking, ASpeedOutwardsFromBeyondALimitIsZeroed) {
    // The gimbal rests at pitch 0, below the soft minimum 5.
    start({}, R"("limits": {"pitch": {"min": 5, "max": 20}})");
    const auto reply = client_->call("speed", {{"pitch", -10}, {"duration_ms", 5000}});
    ASSERT_TRUE(reply.contains("result")) << reply.dump();
    const auto& r = reply["result"];
    EXPECT_EQ(r["speed"], Json({{"roll", 0}, {"pitch", 0}, {"yaw", 0}})) << r.dump();
    EXPECT_EQ(r["braked"], Json::array({"pitch"}));
    EXPECT_EQ(r["duration_ms"], 0);
    EXPECT_TRUE(client_->call("status")["result"]["motion"].is_null());
    // What reached the gimbal: the zero speed, never the outward one.
    bool outwards = false;
    const auto zero = sim_->process().wait_line([&](const std::string& line) {
        const auto j = trace_line(line);
        if (is_control(j, "speed") && j["speed"][1] < 0) {
            outwards = true;
        }
        return is_control(j, "speed") && j["speed"] == Json::array({0, 0, 0});
    });
    EXPECT_TRUE(zero.has_value());
    EXPECT_FALSE(outwards) << "a speed driving further past the limit reached the gimbal";
}

TEST_F(Braking, AStaleLinkWithASoftLimitEndsTheMotionWithNoAttitude) {
    start({"--silence-every", "1500", "--silence-for", "3000"},
          R"("limits": {"pitch": {"min": -60, "max": 60}})");
    // Retry if the silence began between the link coming up and the command.
    Json reply;
    ASSERT_TRUE(eventually([&] {
        reply = client_->call("speed", {{"pitch", 3}, {"duration_ms", 30000}});
        return reply.contains("result");
    })) << reply.dump();
    const auto ended = motion_where([](const Json& p) { return p.value("change", "") == "ended"; });
    ASSERT_TRUE(ended.has_value());
    EXPECT_EQ(ended->value("reason", ""), "no_attitude") << ended->dump();
    EXPECT_TRUE(sim_->wait_speed({0, 0, 0})) << "no zero speed reached the gimbal";
    // While the attitude is stale, a speed towards the limit is refused.
    const auto refused = client_->call("speed", {{"pitch", 3}});
    ASSERT_TRUE(refused.contains("error")) << refused.dump();
    EXPECT_EQ(refused["error"]["code"], -32000);
    EXPECT_NE(refused["error"]["message"].get<std::string>().find("no fresh attitude"),
              std::string::npos)
        << refused.dump();
}

TEST_F(Braking, ASpeedTowardsASoftLimitStopsThatAxisBeforeItWhileAnotherKeepsMoving) {
    // Mechanically pitch reaches ±40; the soft limit is 20.
    start({"--limits", "45,40,170"}, R"("limits": {"pitch": {"min": -60, "max": 20}})");
    const auto reply = client_->call("speed", {{"pitch", 30}, {"yaw", 20}, {"duration_ms", 30000}});
    ASSERT_TRUE(reply.contains("result")) << reply.dump();
    EXPECT_EQ(reply["result"]["braked"], Json::array());
    const auto braked =
        motion_where([](const Json& p) { return p.value("reason", "") == "limit"; });
    ASSERT_TRUE(braked.has_value());
    EXPECT_EQ(braked->value("change", ""), "updated") << braked->dump();
    EXPECT_EQ((*braked)["braked"], Json::array({"pitch"}));
    EXPECT_EQ((*braked)["speed"], Json({{"roll", 0}, {"pitch", 0}, {"yaw", 20}}));
    EXPECT_TRUE(sim_->wait_speed({0, 0, 2000})) << "pitch zeroed, yaw still sent";
    std::this_thread::sleep_for(500ms);
    const auto first = hall();
    std::this_thread::sleep_for(500ms);
    const auto second = hall();
    // The braking distance at 30 °/s: 30 × (one 100 ms keepalive period +
    // the sample's age) + the 1° margin, about 4.5°; allow for a slow loop.
    EXPECT_LE(second["pitch"].get<double>(), 20.0) << second.dump();
    EXPECT_GE(second["pitch"].get<double>(), 20.0 - 8.0) << second.dump();
    EXPECT_EQ(first["pitch"], second["pitch"]) << "pitch stands still";
    EXPECT_GT(second["yaw"].get<double>(), first["yaw"].get<double>() + 3.0) << "yaw moves on";
    const auto status = client_->call("status")["result"]["motion"];
    EXPECT_EQ(status["speed"], Json({{"roll", 0}, {"pitch", 0}, {"yaw", 20}})) << status.dump();
    EXPECT_GE(status["elapsed_ms"].get<int>(), 1000) << status.dump();
    ASSERT_TRUE(client_->call("stop").contains("result"));
}

TEST_F(Braking, AHungStreamingClientIsStoppedByItsLeaseAndTheFailsafeApplies) {
    start({}, R"("failsafe": {"on_owner_gone": "center"})");
    Client streamer(daemon_->socket());
    ASSERT_TRUE(streamer.connected());
    for (int i = 0; i < 5; ++i) {
        const auto reply =
            streamer.call("speed", {{"yaw", 12}, {"duration_ms", 30000}, {"lease_ms", 400}});
        ASSERT_TRUE(reply.contains("result")) << reply.dump();
        std::this_thread::sleep_for(50ms);
    }
    const auto motion = client_->call("status")["result"]["motion"];
    ASSERT_TRUE(motion.is_object()) << motion.dump();
    EXPECT_LE(motion["time_left_ms"].get<int>(), 400) << "the lease ends it first";
    EXPECT_TRUE(motion.contains("elapsed_ms")) << motion.dump();
    // The streamer now hangs: its socket stays open, nothing more is sent.
    const auto ended = motion_where([](const Json& p) { return p.value("change", "") == "ended"; });
    ASSERT_TRUE(ended.has_value());
    EXPECT_EQ(ended->value("reason", ""), "lease_expired");
    EXPECT_TRUE(sim_->wait_speed({0, 0, 0})) << "no zero speed after the lease ran out";
    EXPECT_TRUE(sim_->process().wait_line([](const std::string& l) {
        return is_control(trace_line(l), "center");
    })) << "no centre frame: failsafe.on_owner_gone was not applied";
    EXPECT_TRUE(streamer.connected());
}

}  // namespace
}  // namespace gport::testing
