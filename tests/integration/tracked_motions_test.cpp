// Issue 12, item 4 end to end: angle and centre are tracked motions that know
// when they are done. The real gportd on gport-sim, whose mechanical limits
// (pitch ±90°) make a target beyond them unreachable.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <thread>

#include "sim_daemon_fixture.hpp"

namespace gport::testing {
namespace {

class TrackedMotions : public SimDaemonTest {
  protected:
    std::string config_extra() const override {
        // No stall detection here: an unreachable target ends by the timeout.
        return R"("motion": {"tolerance_deg": 0.5, "timeout_ms": 1500, "stall_ms": 0})";
    }

    // Sends a request without reading its reply; returns its id.
    int send(Client& c, const std::string& method, Json params) {
        const int id = ++next_id_;
        c.send_line(
            Json{{"jsonrpc", "2.0"}, {"id", id}, {"method", method}, {"params", params}}.dump());
        return id;
    }

    // The reply with `id`, skipping notifications and other replies.
    Json reply(Client& c, int id, std::chrono::milliseconds timeout = 15s) {
        const auto deadline = std::chrono::steady_clock::now() + timeout;
        while (std::chrono::steady_clock::now() < deadline) {
            auto message = c.read(std::chrono::duration_cast<std::chrono::milliseconds>(
                deadline - std::chrono::steady_clock::now()));
            if (!message) {
                break;
            }
            if (message->value("id", -1) == id) {
                return *message;
            }
        }
        return Json();
    }

    int gportctl(std::vector<std::string> args, std::string* out = nullptr) {
        args.insert(args.begin(), {GPORTCTL_PATH, "--socket", daemon_->socket()});
        Process process(args);
        while (auto line = process.next_line(30s)) {  // until gportctl's stdout closes
            if (out != nullptr) {
                *out += *line + "\n";
            }
        }
        return process.wait(30s).value_or(-1);
    }

    // The params of the next motion `ended` event `watcher` receives (empty
    // when none comes), skipping the others.
    static Json next_ended(Client& watcher) {
        while (auto n = watcher.notification("motion")) {
            if ((*n)["params"].value("change", "") == "ended") {
                return (*n)["params"];
            }
        }
        return Json::object();
    }

    int next_id_ = 1000;
};

TEST_F(TrackedMotions, AnUnreachableTargetEndsWithTimeout) {
    // gportd's soft limits allow pitch 100°; the simulated gimbal stops at 90°.
    auto result = client_->call("angle", {{"pitch", 100}, {"wait", true}}, 15s)["result"];
    ASSERT_TRUE(result.is_object());
    EXPECT_EQ(result["sent"], true);
    EXPECT_EQ(result["ended"]["reason"], "timeout");
    EXPECT_GE(result["ended"]["elapsed_ms"].get<int>(), 1500);
    EXPECT_NEAR(result["ended"]["attitude"]["hall"]["pitch"].get<double>(), 90.0, 0.01);
    EXPECT_TRUE(client_->call("status")["result"]["motion"].is_null());
}

TEST_F(TrackedMotions, AngleWithWaitRepliesReachedWithTheFinalAttitude) {
    auto result = client_->call(
        "angle", {{"roll", 10}, {"pitch", -30}, {"yaw", 45}, {"wait", true}}, 15s)["result"];
    ASSERT_TRUE(result.is_object());
    EXPECT_EQ(result["ended"]["reason"], "reached");
    const auto hall = result["ended"]["attitude"]["hall"];
    EXPECT_NEAR(hall["roll"].get<double>(), 10.0, 0.5);
    EXPECT_NEAR(hall["pitch"].get<double>(), -30.0, 0.5);
    EXPECT_NEAR(hall["yaw"].get<double>(), 45.0, 0.5);
    EXPECT_TRUE(result["ended"]["attitude"].contains("age_ms"));
    // And back to the centre.
    auto centre = client_->call("center", {{"wait", true}}, 15s)["result"];
    EXPECT_EQ(centre["ended"]["reason"], "reached");
    EXPECT_NEAR(centre["ended"]["attitude"]["hall"]["yaw"].get<double>(), 0.0, 0.5);
}

TEST_F(TrackedMotions, ANewerAngleEndsTheFirstWaiterWithReplaced) {
    Client other(daemon_->socket());
    ASSERT_TRUE(other.connected());
    const int first = send(*client_, "angle", {{"pitch", 80}, {"wait", true}});
    // The first is under way (status shows it) before the second replaces it.
    ASSERT_TRUE(eventually(
        [&] { return client_->call("status")["result"]["motion"].value("mode", "") == "angle"; }));
    auto second = other.call("angle", {{"pitch", -20}, {"wait", true}}, 15s)["result"];
    auto replaced = reply(*client_, first);
    EXPECT_EQ(replaced["result"]["ended"]["reason"], "replaced");
    EXPECT_EQ(second["ended"]["reason"], "reached");
}

TEST_F(TrackedMotions, StopEndsAWaitingAngle) {
    const int id = send(*client_, "angle", {{"yaw", 160}, {"wait", true}});
    Client other(daemon_->socket());
    ASSERT_TRUE(eventually(
        [&] { return other.call("status")["result"]["motion"].value("mode", "") == "angle"; }));
    EXPECT_EQ(other.call("stop")["result"]["sent"], true);
    auto stopped = reply(*client_, id);
    EXPECT_EQ(stopped["result"]["ended"]["reason"], "stop");
    EXPECT_LT(std::fabs(stopped["result"]["ended"]["attitude"]["hall"]["yaw"].get<double>()),
              159.0);
}

TEST_F(TrackedMotions, WatchersSeeStartedAndEnded) {
    Client watcher(daemon_->socket());
    ASSERT_TRUE(watcher.call("subscribe", {{"topics", {"motion"}}}).contains("result"));
    const auto status = client_->call("angle", {{"pitch", 15}})["result"];
    EXPECT_FALSE(status.contains("ended")) << "no wait: the reply is at once";
    auto started = watcher.notification("motion");
    ASSERT_TRUE(started);
    EXPECT_EQ((*started)["params"]["change"], "started");
    EXPECT_EQ((*started)["params"]["mode"], "angle");
    EXPECT_EQ((*started)["params"]["target"]["pitch"], 15.0);
    EXPECT_TRUE((*started)["params"]["owner"].is_object());
    auto ended = watcher.notification("motion");
    ASSERT_TRUE(ended);
    EXPECT_EQ((*ended)["params"]["change"], "ended");
    EXPECT_EQ((*ended)["params"]["reason"], "reached");
    EXPECT_EQ((*ended)["params"]["target"]["pitch"], 15.0);
}

TEST_F(TrackedMotions, AFireAndForgetAngleGoesOnAfterItsOwnerLeaves) {
    Client watcher(daemon_->socket());
    ASSERT_TRUE(watcher.call("subscribe", {{"topics", {"motion"}}}).contains("result"));
    EXPECT_EQ(gportctl({"angle", "--pitch", "40"}), 0);
    EXPECT_EQ(next_ended(watcher).value("reason", ""), "reached");
}

TEST_F(TrackedMotions, AWaiterThatDisconnectsEndsItOwnerGoneWithZeroSpeed) {
    Client watcher(daemon_->socket());
    ASSERT_TRUE(watcher.call("subscribe", {{"topics", {"motion"}}}).contains("result"));
    {
        Client waiter(daemon_->socket());
        send(waiter, "angle", {{"yaw", 160}, {"wait", true}});
        auto started = watcher.notification("motion");
        ASSERT_TRUE(started);
        EXPECT_EQ((*started)["params"]["change"], "started");
    }  // closes the connection while it waits
    auto ended = watcher.notification("motion");
    ASSERT_TRUE(ended);
    EXPECT_EQ((*ended)["params"]["reason"], "owner_gone");
    EXPECT_TRUE(sim_->wait_speed(Json::array({0, 0, 0}))) << "failsafe.on_owner_gone: stop";
}

TEST_F(TrackedMotions, GportctlWaitPrintsTheEndAndExitsByIt) {
    std::string out;
    EXPECT_EQ(gportctl({"angle", "--pitch", "-25", "--wait"}, &out), 0);
    EXPECT_NE(out.find("ended: reached"), std::string::npos) << out;
    out.clear();
    EXPECT_EQ(gportctl({"--json", "angle", "--pitch", "100", "--wait"}, &out), 2) << out;
    auto result = Json::parse(out, nullptr, false);
    ASSERT_TRUE(result.is_object()) << out;
    EXPECT_EQ(result["ended"]["reason"], "timeout");
    EXPECT_EQ(gportctl({"center", "--wait"}), 0);
    EXPECT_EQ(gportctl({"angle", "--pitch", "-100", "--clamp", "--wait"}), 2)
        << "clamped to -100 is still beyond the gimbal's -90";
    EXPECT_EQ(gportctl({"speed", "--yaw", "5", "--for", "300ms", "--lease", "200", "--clamp"}), 0);
}

// Issue 32, item 2: a target beyond the gimbal's reach ends as soon as the
// gimbal has stopped short of it (no progress for motion.stall_ms), saying
// where, instead of waiting out the timeout.
class Stalls : public TrackedMotions {
  protected:
    std::string config_extra() const override {
        return R"("motion": {"timeout_ms": 600000, "stall_ms": 500})";
    }
};

TEST_F(Stalls, ATargetBeyondReachEndsStalledNamingWhereTheGimbalStopped) {
    Client watcher(daemon_->socket());
    ASSERT_TRUE(watcher.call("subscribe", {{"topics", {"motion"}}}).contains("result"));
    auto result = client_->call("angle", {{"pitch", 100}, {"wait", true}}, 60s)["result"];
    ASSERT_TRUE(result.is_object());
    EXPECT_EQ(result["ended"]["reason"], "stalled");
    EXPECT_EQ(result["ended"]["detail"],
              "stalled at pitch 90.00 (target 100.00, 10.00° short): no progress for 500 ms; "
              "beyond the gimbal's reach, or blocked?");
    EXPECT_NEAR(result["ended"]["attitude"]["hall"]["pitch"].get<double>(), 90.0, 0.01);
    EXPECT_LT(result["ended"]["elapsed_ms"].get<int>(), 60000) << "long before the timeout";
    const Json ended = next_ended(watcher);
    EXPECT_EQ(ended.value("reason", ""), "stalled");
    EXPECT_EQ(ended.value("detail", ""), result["ended"]["detail"]);
    EXPECT_TRUE(client_->call("status")["result"]["motion"].is_null());
}

TEST_F(Stalls, AReachableTargetIsReachedNotStalled) {
    // The move itself is progress all the way: a half-second window is enough.
    auto result =
        client_->call("angle", {{"pitch", -60}, {"yaw", 120}, {"wait", true}}, 60s)["result"];
    ASSERT_TRUE(result.is_object());
    EXPECT_EQ(result["ended"]["reason"], "reached");
    EXPECT_FALSE(result["ended"].contains("detail"));
}

TEST_F(Stalls, GportctlPrintsWhereItStoppedAndExits2) {
    std::string out;
    EXPECT_EQ(gportctl({"angle", "--pitch", "-100", "--wait"}, &out), 2) << out;
    EXPECT_NE(out.find("ended: stalled after"), std::string::npos) << out;
    EXPECT_NE(out.find("stalled at pitch -90.00 (target -100.00, 10.00° short)"), std::string::npos)
        << out;
}

}  // namespace
}  // namespace gport::testing
