// The capture log's writer thread and start-up reader (app/): what reaches
// the file, rotation, and the unhappy disks (full, read-only, stalled).
#include "gport/app/capture_writer.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <spdlog/logger.h>
#include <spdlog/sinks/null_sink.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "process.hpp"

namespace gport::app {
namespace {

using nlohmann::json;

std::shared_ptr<spdlog::logger> quiet() {
    return std::make_shared<spdlog::logger>("test",
                                            std::make_shared<spdlog::sinks::null_sink_mt>());
}

std::string capture(std::uint64_t index, std::size_t pad = 0) {
    return json{{"index", index}, {"kind", "photo"}, {"pad", std::string(pad, 'x')}}.dump();
}

std::vector<std::string> lines_of(const std::string& path) {
    std::ifstream in(path);
    std::vector<std::string> out;
    for (std::string line; std::getline(in, line);) {
        out.push_back(line);
    }
    return out;
}

class CaptureWriterTest : public ::testing::Test {
  protected:
    testing::TempDir tmp_;
    CaptureFiles files_{tmp_.file("state"), 1048576, 4};
};

TEST_F(CaptureWriterTest, WritesOneLinePerCaptureAndStartUpReadsThemBack) {
    {
        CaptureWriter writer(files_, quiet());
        for (std::uint64_t i = 1; i <= 3; ++i) {
            writer.write(capture(i));
        }
        writer.drain();
        EXPECT_EQ(writer.stats().written, 3u);
        EXPECT_EQ(writer.stats().dropped, 0u);
        EXPECT_FALSE(writer.stats().error);
    }
    EXPECT_EQ(lines_of(files_.file(0)), (std::vector{capture(1), capture(2), capture(3)}));
    const auto restored = read_captures(files_, 100);
    EXPECT_EQ(restored.lines.size(), 3u);
    EXPECT_EQ(restored.next_index, 4u);
    EXPECT_TRUE(restored.problems.empty());
}

TEST_F(CaptureWriterTest, ALineCutShortIsEndedAndSkippedOnRestore) {
    std::filesystem::create_directory(files_.dir);
    std::ofstream(files_.file(0)) << capture(5) << "\n{\"index\":6,\"ki";  // a crash mid-line
    {
        CaptureWriter writer(files_, quiet());
        writer.write(capture(7));
    }
    const auto restored = read_captures(files_, 100);
    EXPECT_EQ(restored.lines, (std::vector{capture(5), capture(7)}));
    EXPECT_EQ(restored.next_index, 8u);
    ASSERT_EQ(restored.problems.size(), 1u);
    EXPECT_NE(restored.problems[0].find("1 line(s)"), std::string::npos);
}

TEST_F(CaptureWriterTest, RotatesBySizeKeepingNFiles) {
    files_.max_file_bytes = 4096;
    files_.keep_files = 3;
    const std::size_t per_file = 4096 / (capture(1, 400).size() + 1);
    const std::uint64_t total = per_file * 5 + 2;  // more than three files hold
    {
        CaptureWriter writer(files_, quiet());
        for (std::uint64_t i = 1; i <= total; ++i) {
            writer.write(capture(i, 400));
            writer.drain();  // the queue is not under test here
        }
        EXPECT_EQ(writer.stats().written, total);
    }
    for (int n = 0; n < 3; ++n) {
        ASSERT_TRUE(std::filesystem::exists(files_.file(n))) << files_.file(n);
        EXPECT_LE(std::filesystem::file_size(files_.file(n)), 4096u);
    }
    EXPECT_FALSE(std::filesystem::exists(files_.file(3))) << "only keep_files are kept";
    const auto restored = read_captures(files_, 100000);
    EXPECT_EQ(restored.next_index, total + 1);
    ASSERT_FALSE(restored.lines.empty());
    EXPECT_EQ(restored.lines.back(), capture(total, 400));
    // Oldest first and contiguous: rotation drops only the oldest.
    const auto first = json::parse(restored.lines.front())["index"].get<std::uint64_t>();
    EXPECT_EQ(first + restored.lines.size() - 1, total);
    EXPECT_GT(first, 1u);
}

TEST_F(CaptureWriterTest, AFullDiskCountsDropsKeepsTheErrorAndIsNotReadAtStart) {
    std::filesystem::create_directory(files_.dir);
    std::filesystem::create_symlink("/dev/full", files_.file(0));  // every write: ENOSPC
    CaptureWriter writer(files_, quiet());
    for (std::uint64_t i = 1; i <= 5; ++i) {
        writer.write(capture(i));
    }
    writer.drain();
    const auto stats = writer.stats();
    EXPECT_EQ(stats.written, 0u);
    EXPECT_EQ(stats.dropped, 5u);
    ASSERT_TRUE(stats.error);
    EXPECT_NE(stats.error->find("No space left on device"), std::string::npos) << *stats.error;
    EXPECT_NE(stats.error->find(files_.file(0)), std::string::npos) << "names the file";
    const auto restored = read_captures(files_, 100);  // /dev/full would read zeros forever
    EXPECT_EQ(restored.next_index, 1u);
    ASSERT_EQ(restored.problems.size(), 1u);
    EXPECT_NE(restored.problems[0].find("not a regular file"), std::string::npos);
}

TEST_F(CaptureWriterTest, AReadOnlyDirectoryIsAnErrorAndAWritableOneClearsIt) {
    if (::geteuid() == 0) {
        GTEST_SKIP() << "root writes into a read-only directory; the full-disk test covers "
                        "write errors as root";
    }
    std::filesystem::create_directory(files_.dir);
    ::chmod(files_.dir.c_str(), 0555);
    CaptureWriter writer(files_, quiet());
    writer.write(capture(1));
    writer.drain();
    ASSERT_TRUE(writer.stats().error);
    EXPECT_NE(writer.stats().error->find("Permission denied"), std::string::npos);
    ::chmod(files_.dir.c_str(), 0755);
    writer.write(capture(2));
    writer.drain();
    EXPECT_FALSE(writer.stats().error) << "a write that succeeds clears the error";
    EXPECT_EQ(writer.stats().written, 1u);
    EXPECT_EQ(writer.stats().dropped, 1u);
}

// A disk that stalls: the file is a FIFO nobody reads, so the thread's open()
// blocks. write() must still return at once, dropping beyond the queue.
TEST_F(CaptureWriterTest, AStalledDiskNeverBlocksTheCallerAndDropsBeyondTheQueue) {
    std::filesystem::create_directory(files_.dir);
    ASSERT_EQ(::mkfifo(files_.file(0).c_str(), 0600), 0);
    constexpr std::size_t kQueue = 4;
    CaptureWriter writer(files_, quiet(), kQueue);
    for (std::uint64_t i = 1; i <= 10; ++i) {
        writer.write(capture(i));  // returns although the thread is stuck in open()
    }
    EXPECT_GE(writer.stats().dropped, 10 - kQueue - 1);
    const int reader = ::open(files_.file(0).c_str(), O_RDONLY | O_NONBLOCK);  // unstalls it
    ASSERT_GE(reader, 0);
    writer.drain();
    const auto stats = writer.stats();
    EXPECT_EQ(stats.written + stats.dropped, 10u);
    EXPECT_GE(stats.written, kQueue);
    ::close(reader);
}

}  // namespace
}  // namespace gport::app
