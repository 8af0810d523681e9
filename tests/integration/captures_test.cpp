// The capture log end to end (issue 25): the real gportd --simulate over its
// socket, its files in a state directory of the test's, restarted, on a full
// disk and a tiny one, and read back by gportctl captures --csv.
#include <gtest/gtest.h>
#include <sys/mount.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "harness.hpp"

namespace gport::testing {
namespace {

class CapturesEndToEnd : public ::testing::Test {
  protected:
    void start(const std::string& config_extra = "") {
        daemon_ = std::make_unique<DaemonProcess>(
            dir_, std::vector<std::string>{"--simulate", "--state-dir", state_},
            std::vector<std::string>{}, config_extra);
        client_ = std::make_unique<Client>(daemon_->socket());
        ASSERT_TRUE(client_->connected());
        ASSERT_TRUE(link_up(*client_));
    }
    void stop() {
        client_.reset();
        daemon_->process().signal(SIGTERM);
        EXPECT_EQ(daemon_->process().wait(), 0);
        daemon_.reset();
    }
    Json captures(const Json& params = nullptr) {
        return client_->call("captures", params)["result"];
    }
    Json status_captures() { return client_->call("status")["result"]["captures"]; }
    // Waits until the writer has dealt with every capture taken.
    bool settled(std::uint64_t taken) {
        return eventually([&] {
            auto s = status_captures();
            return s["written"].get<std::uint64_t>() + s["dropped"].get<std::uint64_t>() == taken;
        });
    }

    TempDir dir_;
    std::string state_ = dir_.file("state");
    std::unique_ptr<DaemonProcess> daemon_;
    std::unique_ptr<Client> client_;
};

TEST_F(CapturesEndToEnd, PersistedAndListedAfterARestartWithIndexesContinuing) {
    start();
    EXPECT_EQ(client_->call("photo", {{"meta", {{"wp", 3}}}})["result"]["capture"]["index"], 1);
    EXPECT_EQ(client_->call("record", {{"on", true}, {"force", true}})["result"]["capture"]["kind"],
              "record_start");
    EXPECT_EQ(client_->call("record", {{"on", false}})["result"]["capture"]["index"], 3);
    const auto before = captures()["captures"];
    ASSERT_TRUE(settled(3));
    stop();

    start();
    const auto after = captures();
    EXPECT_EQ(after["captures"], before) << "the same captures, read back from the file";
    EXPECT_EQ(after["next"], 4);
    EXPECT_EQ(client_->call("photo")["result"]["capture"]["index"], 4) << "never reused";
    EXPECT_EQ(status_captures()["next_index"], 5);
    EXPECT_EQ(status_captures()["file"], state_ + "/captures.jsonl");
}

TEST_F(CapturesEndToEnd, RotationKeepsNFilesAndTheIndexesAcrossARestart) {
    const std::string config = R"("captures": {"max_file_bytes": 4096, "keep_files": 2})";
    start(config);
    const Json meta = {{"note", std::string(600, 'n')}};
    for (int i = 0; i < 30; ++i) {
        ASSERT_EQ(client_->call("photo", {{"meta", meta}})["result"]["sent"], true);
    }
    ASSERT_TRUE(settled(30));
    stop();
    EXPECT_TRUE(std::filesystem::exists(state_ + "/captures.jsonl.1"));
    EXPECT_FALSE(std::filesystem::exists(state_ + "/captures.jsonl.2"));
    EXPECT_LE(std::filesystem::file_size(state_ + "/captures.jsonl"), 4096u);

    start(config);
    const auto kept = captures({{"limit", 1000}})["captures"];
    ASSERT_FALSE(kept.empty());
    EXPECT_EQ(kept.back()["index"], 30);
    EXPECT_GT(kept.front()["index"], 1) << "the oldest went with the oldest file";
    EXPECT_EQ(client_->call("photo")["result"]["capture"]["index"], 31);
}

// Every write fails (the file is /dev/full): the daemon keeps serving, the
// stop still reaches the gimbal, the captures stay listed from memory, and
// status says what went wrong.
TEST_F(CapturesEndToEnd, AFullDiskLosesNoStopKeepsServingAndShowsTheError) {
    std::filesystem::create_directory(state_);
    std::filesystem::create_symlink("/dev/full", state_ + "/captures.jsonl");
    start();
    ASSERT_EQ(
        client_->call("speed", {{"yaw", 10}, {"duration_ms", 5000}})["result"]["speed"]["yaw"], 10);
    for (int i = 0; i < 5; ++i) {
        ASSERT_EQ(client_->call("photo")["result"]["sent"], true);
    }
    const auto stops = client_->call("status")["result"]["counters"]["stops_sent"];
    ASSERT_EQ(client_->call("stop")["result"]["sent"], true);
    EXPECT_TRUE(eventually([&] {
        return client_->call("status")["result"]["counters"]["stops_sent"] > stops;
    })) << "the stop reached the gimbal";
    ASSERT_TRUE(settled(5));
    const auto s = status_captures();
    EXPECT_EQ(s["dropped"], 5);
    EXPECT_EQ(s["written"], 0);
    ASSERT_TRUE(s["error"].is_string());
    EXPECT_TRUE(contains(s["error"], "No space left on device")) << s;
    EXPECT_EQ(captures()["captures"].size(), 5u) << "kept in memory";
    EXPECT_EQ(client_->call("attitude")["result"].contains("imu"), true) << "still serving";
}

// A real filesystem that fills up: a 64 KiB tmpfs (root only).
TEST_F(CapturesEndToEnd, ATinyTmpfsFillsUpWithoutLosingTheStop) {
    std::filesystem::create_directory(state_);
    if (::geteuid() != 0) {
        GTEST_SKIP() << "mounting a 64 KiB tmpfs needs root; the /dev/full test covers a full "
                        "disk without it";
    }
    if (::mount("tmpfs", state_.c_str(), "tmpfs", 0, "size=64k") != 0) {
        GTEST_SKIP() << "cannot mount a tmpfs here (" << std::strerror(errno)
                     << "); the /dev/full test covers a full disk";
    }
    struct Unmount {
        std::string path;
        ~Unmount() { ::umount2(path.c_str(), MNT_DETACH); }
    } unmount{state_};
    start(R"("captures": {"max_file_bytes": 1048576, "keep_files": 2})");
    const Json meta = {{"note", std::string(1000, 'n')}};
    int taken = 0;
    while (status_captures()["error"].is_null() && taken < 200) {
        ASSERT_EQ(client_->call("photo", {{"meta", meta}})["result"]["sent"], true);
        ++taken;
        ASSERT_TRUE(settled(static_cast<std::uint64_t>(taken)));
    }
    const auto s = status_captures();
    ASSERT_TRUE(s["error"].is_string()) << "64 KiB never filled: " << s;
    EXPECT_TRUE(contains(s["error"], "No space left on device")) << s;
    EXPECT_GT(s["written"], 0);
    const auto stops = client_->call("status")["result"]["counters"]["stops_sent"];
    ASSERT_EQ(client_->call("stop")["result"]["sent"], true);
    EXPECT_TRUE(eventually(
        [&] { return client_->call("status")["result"]["counters"]["stops_sent"] > stops; }));
    EXPECT_EQ(client_->call("photo")["result"]["capture"]["index"], taken + 1);
}

}  // namespace
}  // namespace gport::testing
