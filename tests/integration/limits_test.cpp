// Issue 12 end to end: the soft limits of the config file, applied by the real
// gportd to angle and speed commands, seen on the real gport-sim's trace.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "harness.hpp"

namespace gport::testing {
namespace {

using ::testing::HasSubstr;

class LimitsEndToEnd : public ::testing::Test {
  protected:
    void SetUp() override {
        sim_ = std::make_unique<SimProcess>(dir_);
        daemon_ = std::make_unique<DaemonProcess>(
            dir_, std::vector<std::string>{"--device", sim_->link()}, std::vector<std::string>{},
            R"("limits": {"pitch": {"min": -90, "max": 30}, "max_speed": 50})");
        client_ = std::make_unique<Client>(daemon_->socket());
        ASSERT_TRUE(client_->connected());
        ASSERT_TRUE(link_up(*client_));
    }

    // Waits for a trace line of an angle frame equal to [roll, pitch, yaw].
    bool wait_angle(const Json& angle) {
        return sim_->process()
            .wait_line([&](const std::string& line) {
                auto j = Json::parse(line, nullptr, false);
                return j.is_object() && j.value("mode", "") == "angle" && j["angle"] == angle;
            })
            .has_value();
    }

    TempDir dir_;
    std::unique_ptr<SimProcess> sim_;
    std::unique_ptr<DaemonProcess> daemon_;
    std::unique_ptr<Client> client_;
};

TEST_F(LimitsEndToEnd, AnAngleOutsideTheLimitsIsRefusedNamingAxisAndRange) {
    auto reply = client_->call("angle", {{"pitch", -100}});
    EXPECT_EQ(reply["error"]["code"], -32602);
    EXPECT_THAT(reply["error"]["message"].get<std::string>(),
                HasSubstr("pitch = -100 is outside the soft limit -90 to 30 (limits.pitch)"));
    // Within the limits it is sent as asked.
    EXPECT_EQ(client_->call("angle", {{"pitch", 20}})["result"]["sent"], true);
    EXPECT_TRUE(wait_angle({0, 2000, 0}));
}

TEST_F(LimitsEndToEnd, AClampedAngleReachesTheGimbalClamped) {
    auto result = client_->call("angle", {{"pitch", -100}, {"yaw", 45}, {"clamp", true}})["result"];
    EXPECT_EQ(result["sent"], true);
    EXPECT_EQ(result["angle"], Json({{"roll", 0.0}, {"pitch", -90.0}, {"yaw", 45.0}}));
    EXPECT_EQ(result["clamped"], Json({"pitch"}));
    EXPECT_TRUE(wait_angle({0, -9000, 4500}));
}

TEST_F(LimitsEndToEnd, ATooFastSpeedIsRefusedOrClamped) {
    auto refused = client_->call("speed", {{"yaw", 80}});
    EXPECT_EQ(refused["error"]["code"], -32602);
    EXPECT_THAT(refused["error"]["message"].get<std::string>(),
                HasSubstr("yaw = 80 °/s is faster than the soft limit 50 °/s (limits.max_speed)"));

    auto result = client_->call(
        "speed", {{"yaw", -80}, {"roll", 10}, {"clamp", true}, {"duration_ms", 500}})["result"];
    EXPECT_EQ(result["speed"], Json({{"roll", 10.0}, {"pitch", 0.0}, {"yaw", -50.0}}));
    EXPECT_EQ(result["clamped"], Json({"yaw"}));
    EXPECT_TRUE(sim_->wait_speed({1000, 0, -5000}));
    EXPECT_EQ(client_->call("stop")["result"]["sent"], true);
}

// Item 5 of issue 22: with pitch limited to -60..-10 and the failsafe centre,
// center (and the failsafe) drive pitch to -10, never to 0; the start warns.
TEST(CentreEndToEnd, CenterAndItsFailsafeStayInsideTheLimitsAndTheStartWarns) {
    TempDir dir;
    SimProcess sim(dir);
    const std::string command =
        std::string("exec ") + GPORTD_PATH + " --config " +
        write_test_config(dir, R"("limits": {"pitch": {"min": -60, "max": -10}},
  "failsafe": {"on_owner_gone": "center"})") +
        " --socket " + dir.file("gportd.sock") + " --device " + sim.link() + " 2>&1";
    Process daemon({"/bin/sh", "-c", command});
    const auto warning = daemon.wait_line([](const std::string& line) {
        return contains(line,
                        "failsafe.on_owner_gone is \"center\", but 0° lies outside "
                        "limits.pitch (-60 to -10)");
    });
    ASSERT_TRUE(warning) << "no start warning";
    EXPECT_TRUE(contains(*warning, "[warning]")) << *warning;
    Client client(dir.file("gportd.sock"));
    ASSERT_TRUE(link_up(client));

    const auto result = client.call("center")["result"];
    EXPECT_EQ(result["target"], Json({{"roll", 0.0}, {"pitch", -10.0}, {"yaw", 0.0}}));
    EXPECT_EQ(result["clamped"], Json({"pitch"}));
    const auto is_angle_to = [](const Json& angle) {
        return [angle](const std::string& line) {
            auto j = Json::parse(line, nullptr, false);
            return j.is_object() && j.value("mode", "") == "angle" && j["angle"] == angle;
        };
    };
    EXPECT_TRUE(sim.process().wait_line(is_angle_to({0, -1000, 0})));

    // The failsafe: a waiting owner leaves while its angle motion runs.
    {
        Client owner(dir.file("gportd.sock"));
        owner.send_line(R"({"id":1,"method":"angle","params":{"pitch":-55,"wait":true}})");
        EXPECT_TRUE(sim.process().wait_line(is_angle_to({0, -5500, 0})));
    }
    EXPECT_TRUE(sim.process().wait_line(is_angle_to({0, -1000, 0})))
        << "the failsafe's centre, clamped";
    EXPECT_FALSE(sim.process().wait_line(
        [](const std::string& line) {
            auto j = Json::parse(line, nullptr, false);
            return j.is_object() && j.value("mode", "") == "center";
        },
        500ms))
        << "the gimbal's own centre command would drive pitch to 0";
}

}  // namespace
}  // namespace gport::testing
