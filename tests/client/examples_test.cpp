// The C++ examples (examples/cpp/) run against gportd --simulate.
#include <csignal>
#include <regex>
#include <sstream>

#include "client_fixture.hpp"

namespace gport::testing {
namespace {

using Examples = SimulatedDaemonTest;

std::vector<std::string> lines_until_exit(Process& p, std::optional<int>& status) {
    std::vector<std::string> lines;
    while (auto line = p.next_line(30s)) {
        lines.push_back(*line);
    }
    status = p.wait(30s);
    return lines;
}

TEST_F(Examples, AttitudeCsvWritesTimestampedRows) {
    Process example({ATTITUDE_CSV_PATH, socket(), "20", "50"});
    std::optional<int> status;
    const auto lines = lines_until_exit(example, status);
    ASSERT_EQ(status, 0);
    ASSERT_EQ(lines.size(), 21U);
    EXPECT_EQ(lines[0], "seq,time,imu_roll,imu_pitch,imu_yaw,hall_roll,hall_pitch,hall_yaw");
    long last_seq = -1;
    for (std::size_t i = 1; i < lines.size(); ++i) {
        std::istringstream row(lines[i]);
        std::vector<std::string> cells;
        for (std::string cell; std::getline(row, cell, ',');) {
            cells.push_back(cell);
        }
        ASSERT_EQ(cells.size(), 8U) << lines[i];
        const long seq = std::stol(cells[0]);
        EXPECT_GT(seq, last_seq) << "rows in order";
        last_seq = seq;
        EXPECT_GT(std::stod(cells[1]), 1.6e9) << "seconds since the epoch: " << lines[i];
    }
}

TEST_F(Examples, TrackerStreamsSpeedWithALeaseAndStops) {
    const auto updates_before = client().status().counters.motion_updates;
    Process example({TRACKER_PATH, socket(), "2"});
    std::optional<int> status;
    const auto lines = lines_until_exit(example, status);
    ASSERT_EQ(status, 0);
    ASSERT_EQ(lines.size(), 1U);
    EXPECT_EQ(lines[0].rfind("sent ", 0), 0U) << lines[0];
    EXPECT_GT(std::stoi(lines[0].substr(5)), 5) << "about 40 at 20 Hz for 2 s: " << lines[0];
    const auto s = client().status();
    EXPECT_GT(s.counters.motion_updates, updates_before) << "the stream updated one motion";
    EXPECT_FALSE(s.motion.has_value()) << "stopped at the end";
}

TEST_F(Examples, SweepAndPhotoWaitsAtEachPosition) {
    try {
        client().angle({}, {.wait = true});
    } catch (const gc::Error& e) {
        // `wait` comes with tracked motions (helper "track", issue 12 item 4);
        // until this daemon has it, it refuses the parameter. Re-enabled at the merge.
        if (e.code() == -32602 && e.message().find("wait") != std::string::npos) {
            GTEST_SKIP() << "this gportd has no `wait` yet: " << e.what();
        }
        throw;
    }
    Process example({SWEEP_AND_PHOTO_PATH, socket()});
    std::optional<int> status;
    const auto lines = lines_until_exit(example, status);
    ASSERT_EQ(status, 0);
    std::vector<std::string> photos;
    for (const auto& line : lines) {
        if (line.rfind("photo at yaw ", 0) == 0) {
            photos.push_back(line);
        }
    }
    EXPECT_EQ(photos.size(), 3U);
    ASSERT_FALSE(lines.empty());
    EXPECT_EQ(lines.back(), "centred");
}

// docs/client-cpp.md's notifications snippet, compiled as written: the time
// with its milliseconds, not 1.79553e+09 (issue 26).
TEST_F(Examples, DocSnippetPrintsTheTimeInFull) {
    // The snippet prints "\n", not std::endl: a pipe would hold its lines, a
    // terminal has them line-buffered. `script` (util-linux) gives it one.
    // (Not stdbuf: its LD_PRELOAD library is this machine's, of no use to a
    // cross build's program under qemu-user.) The terminal ends lines in CR LF.
    Process snippet({"/usr/bin/script", "-qfec",
                     std::string(DOC_SNIPPET_PATH) + " '" + socket() + "'", "/dev/null"});
    std::vector<std::string> lines;
    while (lines.size() < 3) {
        auto line = snippet.next_line(10s);
        ASSERT_TRUE(line) << "no attitude line from the snippet";
        if (!line->empty() && line->back() == '\r') {
            line->pop_back();
        }
        lines.push_back(*line);
    }
    snippet.signal(SIGTERM);
    snippet.wait();
    const std::regex kLine(R"(^[0-9]{10}\.[0-9]{3} yaw [-0-9.]+$)");
    for (const auto& line : lines) {
        EXPECT_TRUE(std::regex_match(line, kLine)) << line;
        EXPECT_EQ(line.find('e'), std::string::npos) << "no exponent: " << line;
    }
}

}  // namespace
}  // namespace gport::testing
