// Issue 12, item 5 end to end: a client streaming speed commands (a joystick)
// makes one motion, logged once at info and notified at most twice a second
// while it lasts; a streaming client that hangs with its socket open is
// stopped by its lease.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>

#include "harness.hpp"

namespace gport::testing {
namespace {

bool has(const std::string& line, const std::string& what) {
    return line.find(what) != std::string::npos;
}

// gportd at --log-level info, its stderr on the Process's stdout (a shell
// execs it, so the pid is gportd's).
class InfoDaemon {
  public:
    InfoDaemon(const TempDir& dir, const std::string& device) : socket_(dir.file("gportd.sock")) {
        const std::string command = std::string("exec ") + GPORTD_PATH + " --config " +
                                    write_test_config(dir) + " --socket " + socket_ + " --device " +
                                    device + " --log-level info 2>&1";
        process_ = std::make_unique<Process>(std::vector<std::string>{"/bin/sh", "-c", command});
    }
    const std::string& socket() const { return socket_; }
    Process& process() { return *process_; }

  private:
    std::string socket_;
    std::unique_ptr<Process> process_;
};

class Leases : public ::testing::Test {
  protected:
    void SetUp() override {
        daemon_ = std::make_unique<InfoDaemon>(dir_, sim_.link());
        watcher_ = std::make_unique<Client>(daemon_->socket());
        ASSERT_TRUE(watcher_->connected());
        ASSERT_TRUE(link_up(*watcher_));
        ASSERT_TRUE(watcher_->call("subscribe", {{"topics", {"motion"}}}).contains("result"));
        streamer_ = std::make_unique<Client>(daemon_->socket());
        ASSERT_TRUE(streamer_->connected());
    }

    // The watcher's motion notifications up to and including the "ended" one.
    std::vector<Json> motion_until_ended() {
        std::vector<Json> seen;
        while (auto n = watcher_->notification("motion")) {
            seen.push_back((*n)["params"]);
            if (seen.back().value("change", "") == "ended") {
                break;
            }
        }
        return seen;
    }

    static std::size_t count(const std::vector<Json>& events, const std::string& change) {
        std::size_t n = 0;
        for (const auto& e : events) {
            n += e.value("change", "") == change ? 1 : 0;
        }
        return n;
    }

    TempDir dir_;
    SimProcess sim_{dir_};
    std::unique_ptr<InfoDaemon> daemon_;
    std::unique_ptr<Client> watcher_;
    std::unique_ptr<Client> streamer_;
};

TEST_F(Leases, AStreamingClientMakesOneMotionAndFewNotifications) {
    const auto began = std::chrono::steady_clock::now();
    for (int i = 0; i < 60; ++i) {  // 20 Hz for about 3 s
        const auto reply = streamer_->call("speed", {{"yaw", 5 + (i % 10)}, {"duration_ms", 1000}});
        ASSERT_TRUE(reply.contains("result")) << reply.dump();
        std::this_thread::sleep_for(50ms);
    }
    const auto streamed = std::chrono::steady_clock::now() - began;
    const auto status = watcher_->call("status")["result"];
    EXPECT_EQ(status["counters"]["motion_updates"], 59) << status.dump();
    ASSERT_TRUE(streamer_->call("stop").contains("result"));

    const auto events = motion_until_ended();
    ASSERT_FALSE(events.empty());
    EXPECT_EQ(events.front().value("change", ""), "started");
    EXPECT_EQ(events.back().value("change", ""), "ended");
    EXPECT_EQ(events.back().value("reason", ""), "stop");
    EXPECT_EQ(count(events, "started"), 1U);
    EXPECT_EQ(count(events, "replaced"), 0U);
    // At most 2 "updated" a second (one more for rounding).
    const auto allowed = static_cast<std::size_t>(streamed / 500ms) + 1;
    EXPECT_LE(count(events, "updated"), allowed);
    EXPECT_GE(count(events, "updated"), 1U);

    // The journal: one line when it started, one when it ended.
    std::size_t started = 0;
    std::size_t replaced = 0;
    std::size_t updated = 0;
    const auto ended = daemon_->process().wait_line([&](const std::string& line) {
        started += has(line, "motion started") ? 1 : 0;
        replaced += has(line, "motion replaced") ? 1 : 0;
        updated += has(line, "motion updated") ? 1 : 0;
        return has(line, "motion ended");
    });
    ASSERT_TRUE(ended.has_value());
    EXPECT_TRUE(has(*ended, "(stop)")) << *ended;
    EXPECT_EQ(started, 1U);
    EXPECT_EQ(replaced, 0U);
    EXPECT_EQ(updated, 0U) << "updates are logged at debug";
    EXPECT_FALSE(daemon_->process().wait_line(
        [](const std::string& line) { return has(line, "motion "); }, 300ms))
        << "a second motion line";
}

TEST_F(Leases, AHungStreamingClientIsStoppedByItsLease) {
    for (int i = 0; i < 5; ++i) {
        const auto reply =
            streamer_->call("speed", {{"yaw", 12}, {"duration_ms", 30000}, {"lease_ms", 400}});
        ASSERT_TRUE(reply.contains("result")) << reply.dump();
        std::this_thread::sleep_for(50ms);
    }
    ASSERT_TRUE(sim_.wait_speed({0, 0, 1200}));
    // The streamer now hangs: its socket stays open, nothing more is sent.
    const auto events = motion_until_ended();
    ASSERT_FALSE(events.empty());
    EXPECT_EQ(events.back().value("change", ""), "ended");
    EXPECT_EQ(events.back().value("reason", ""), "lease_expired");
    EXPECT_TRUE(sim_.wait_speed({0, 0, 0})) << "no zero speed reached the gimbal";
    EXPECT_TRUE(streamer_->connected());
    EXPECT_TRUE(watcher_->call("status")["result"]["motion"].is_null());

    const auto range = streamer_->call("speed", {{"yaw", 12}, {"lease_ms", 0}});
    ASSERT_TRUE(range.contains("error")) << range.dump();
    EXPECT_NE(range["error"]["message"].get<std::string>().find("lease_ms"), std::string::npos)
        << range.dump();
}

// An autopilot's gimbal manager (through gport-mavlink) or a tracker streams
// angle targets at 50 Hz: one motion, a few notifications, a quiet journal.
TEST_F(Leases, AFiftyHertzPanIsOneMotionAndWritesAtMostSixJournalLines) {
    daemon_->process().drain();  // the start's lines
    const auto began = std::chrono::steady_clock::now();
    int sent = 0;
    while (std::chrono::steady_clock::now() - began < 4s) {
        const double yaw = -40.0 + 0.4 * (sent % 200);  // 20°/s
        const auto reply = streamer_->call("angle", {{"yaw", yaw}, {"pitch", -10}});
        ASSERT_TRUE(reply.contains("result")) << reply.dump();
        ++sent;
        std::this_thread::sleep_for(20ms);
    }
    const auto status = watcher_->call("status")["result"];
    EXPECT_EQ(status["counters"]["motion_updates"], sent - 1) << status.dump();
    EXPECT_EQ(status["motion"]["mode"], "angle") << "still running: the stream went on";
    const auto journal = daemon_->process().drain();
    std::string text;
    for (const auto& line : journal) {
        text += line + "\n";
    }
    EXPECT_LE(journal.size(), 6U) << sent << " angles; the journal:\n" << text;
    EXPECT_TRUE(has(text, "motion started (angle)")) << text;
    EXPECT_FALSE(has(text, "motion ended (replaced)")) << text;

    ASSERT_TRUE(streamer_->call("stop").contains("result"));
    const auto events = motion_until_ended();
    EXPECT_EQ(count(events, "started"), 1U);
    EXPECT_EQ(count(events, "ended"), 1U);
    EXPECT_LE(count(events, "updated"), 9U) << "at most 2 a second";
    EXPECT_GE(count(events, "updated"), 1U);
}

}  // namespace
}  // namespace gport::testing
