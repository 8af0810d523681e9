// Issue 10 end to end: the real gportd on the real gport-sim, whose gimbal
// stops draining the line on SIGUSR1 and resumes on SIGUSR2. A stop must
// reach the gimbal however full the line is, whoever holds control.
#include <gtest/gtest.h>
#include <signal.h>

#include <string>
#include <thread>
#include <vector>

#include "harness.hpp"
#include "sim_daemon_fixture.hpp"

namespace gport::testing {
namespace {

// Requests joined by newlines, sent in one write.
std::string joined(const std::vector<std::string>& lines) {
    std::string out;
    for (const auto& line : lines) {
        out.append(out.empty() ? "" : "\n").append(line);
    }
    return out;
}

std::string request_line(int id, const std::string& method, const Json& params = nullptr) {
    Json r{{"id", id}, {"method", method}};
    if (!params.is_null()) {
        r["params"] = params;
    }
    return r.dump();
}

bool is_speed(const std::string& line) {
    auto j = Json::parse(line, nullptr, false);
    return j.is_object() && j.value("mode", "") == "speed";
}

class StopSafetyEndToEnd : public SimDaemonTest {
  protected:
    void stall_gimbal() {
        sim_->process().signal(SIGUSR1);
        ASSERT_TRUE(sim_->process().wait_line([](const std::string& l) {
            return l.find("\"reading_paused\"") != std::string::npos;
        }));
    }

    // Photos in batches of 100, 50 ms apart, until a whole batch is refused
    // with -32000 (64 wait for the line) and none accepted: gportd hands the
    // line only what it carries, so while the stalled pty still takes bytes
    // its queue drains about 45 frames in 50 ms and some photos of the next
    // batch are accepted; once the pty's buffer is full (about 6 s at the
    // line rate) nothing drains. The camera and request limits are raised
    // for it (config_extra).
    void fill_line() {
        const auto deadline = std::chrono::steady_clock::now() + 120s;
        while (std::chrono::steady_clock::now() < deadline) {
            std::vector<std::string> lines;
            for (int i = 0; i < 100; ++i) {
                lines.push_back(request_line(i, "photo"));
            }
            client_->send_line(joined(lines));
            bool accepted = false;
            bool full = false;
            for (int i = 0; i < 100; ++i) {
                auto reply = client_->read();
                ASSERT_TRUE(reply.has_value());
                accepted = accepted || reply->contains("result");
                full = full || (reply->contains("error") && (*reply)["error"]["code"] == -32000);
            }
            if (full && !accepted) {
                return;
            }
            std::this_thread::sleep_for(50ms);
        }
        FAIL() << "the daemon never refused a whole batch of photos: the line did not fill";
    }

    std::string config_extra() const override {
        return R"("camera": {"max_commands_per_s": 1000}, )"
               R"("socket": {"max_requests_per_s": 100000})";
    }

    Json counters() { return client_->call("status")["result"]["counters"]; }
};

TEST_F(StopSafetyEndToEnd, AStopAfter96SpeedsInOneWriteReachesAStalledGimbal) {
    ASSERT_TRUE(client_->call("speed", {{"yaw", 20}, {"duration_ms", 30000}}).contains("result"));
    ASSERT_TRUE(sim_->wait_speed({0, 0, 2000}));
    ASSERT_NO_FATAL_FAILURE(stall_gimbal());
    ASSERT_NO_FATAL_FAILURE(fill_line());
    std::string lines;
    for (int i = 0; i < 96; ++i) {
        lines +=
            request_line(1000 + i, "speed", {{"yaw", 1 + i % 10}, {"duration_ms", 30000}}) + "\n";
    }
    client_->send_line(lines + request_line(2000, "stop"));
    for (int i = 0; i < 97; ++i) {
        auto reply = client_->read();
        ASSERT_TRUE(reply.has_value());
        EXPECT_TRUE(reply->contains("result")) << reply->dump();
    }
    EXPECT_GE(counters()["frames_replaced"].get<int>(), 95);
    sim_->process().signal(SIGUSR2);
    ASSERT_TRUE(sim_->wait_speed({0, 0, 0})) << "the stop never reached the gimbal";
    ASSERT_TRUE(eventually([&] { return counters()["stops_sent"] == 1; }));
    std::this_thread::sleep_for(300ms);
    for (const auto& line : sim_->process().drain()) {
        EXPECT_FALSE(is_speed(line)) << "a speed after the stop: " << line;
    }
}

TEST_F(StopSafetyEndToEnd, SigtermWithAStalledGimbalStillSendsTheStop) {
    ASSERT_TRUE(client_->call("speed", {{"pitch", 10}, {"duration_ms", 30000}}).contains("result"));
    ASSERT_TRUE(sim_->wait_speed({0, 1000, 0}));
    ASSERT_NO_FATAL_FAILURE(stall_gimbal());
    ASSERT_NO_FATAL_FAILURE(fill_line());
    client_->call("subscribe", {{"topics", {"motion"}}});
    daemon_->process().signal(SIGTERM);
    // Once the motion has ended the stop is queued (or, before issue 10,
    // refused); the line then drains within the daemon's 500 ms limit.
    auto ended = client_->notification("motion");
    ASSERT_TRUE(ended.has_value());
    EXPECT_EQ((*ended)["params"]["reason"], "shutdown");
    sim_->process().signal(SIGUSR2);
    EXPECT_TRUE(sim_->wait_speed({0, 0, 0})) << "no zero speed after SIGTERM";
    EXPECT_EQ(daemon_->process().wait(), 0);
}

TEST_F(StopSafetyEndToEnd, TheOwnerStopsAfterAnotherClientAcquired) {
    client_->call("subscribe", {{"topics", {"motion"}}});
    ASSERT_TRUE(client_->call("speed", {{"roll", 5}, {"duration_ms", 30000}}).contains("result"));
    ASSERT_TRUE(sim_->wait_speed({500, 0, 0}));
    Client other(daemon_->socket());
    ASSERT_TRUE(other.call("acquire")["result"]["you_hold_control"].get<bool>());
    ASSERT_TRUE(sim_->wait_speed({0, 0, 0})) << "acquire did not stop the other's motion";
    bool preempted = false;
    while (auto n = client_->notification("motion", 5s)) {
        if ((*n)["params"].value("reason", "") == "preempted") {
            preempted = true;
            break;
        }
    }
    EXPECT_TRUE(preempted);
    auto stopped = client_->call("stop");
    EXPECT_EQ(stopped["result"]["sent"], true) << stopped.dump();
    EXPECT_TRUE(sim_->wait_speed({0, 0, 0}));
    EXPECT_EQ(client_->call("photo")["error"]["code"], -32003) << "other commands still arbitrated";
}

TEST_F(StopSafetyEndToEnd, SettingsRequestsOverTheCapGetTooMany) {
    ASSERT_NO_FATAL_FAILURE(stall_gimbal());  // settings are never answered
    std::vector<std::string> lines;
    for (int i = 0; i < 5; ++i) {
        lines.push_back(request_line(i, "get_settings"));
    }
    client_->send_line(joined(lines));
    int too_many = 0;
    int no_answer = 0;
    for (int i = 0; i < 5; ++i) {
        auto reply = client_->read();
        ASSERT_TRUE(reply.has_value());
        const int code = reply->value("error", Json::object()).value("code", 0);
        too_many += code == -32005 ? 1 : 0;
        no_answer += code == -32002 ? 1 : 0;
    }
    EXPECT_EQ(too_many, 1);
    EXPECT_EQ(no_answer, 4);
}

}  // namespace
}  // namespace gport::testing
