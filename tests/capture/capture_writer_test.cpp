// The capture log's writer thread: what reaches the file, rotation,
// the index reservation, and the unhappy disks (full, read-only, stalled,
// a planted symlink), first.
#include "gport/capture/capture_writer.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "capture_test_files.hpp"

namespace gport::capture::test {
namespace {

using nlohmann::json;
using namespace std::chrono_literals;

bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

// Reads a FIFO until stopped: a disk that unstalls.
class FifoReader {
  public:
    explicit FifoReader(const std::string& path)
        : fd_(::open(path.c_str(), O_RDONLY | O_NONBLOCK)), thread_([this] { run(); }) {}
    ~FifoReader() {
        stop_ = true;
        thread_.join();
        ::close(fd_);
    }

  private:
    void run() {
        char buffer[65536];
        while (!stop_) {
            if (::read(fd_, buffer, sizeof buffer) <= 0) {
                std::this_thread::sleep_for(1ms);
            }
        }
    }
    int fd_;
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

using CaptureWriterTest = CaptureFilesTest;

// A planted symlink: never followed, its target untouched.
TEST_F(CaptureWriterTest, ASymlinkedLogFileIsRefusedNotFollowed) {
    const auto target = tmp_.file("elsewhere");
    std::ofstream(target) << "precious\n";
    std::filesystem::create_symlink(target, files_.file(0));
    CaptureWriter writer(files_, 1001, log_.logger);
    for (std::uint64_t i = 1; i <= 3; ++i) {
        writer.write(capture(i));
    }
    writer.drain();
    const auto stats = writer.stats();
    EXPECT_EQ(stats.written, 0u);
    EXPECT_EQ(stats.dropped, 3u);
    ASSERT_TRUE(stats.error);
    EXPECT_TRUE(contains(*stats.error, "symbolic link")) << *stats.error;
    EXPECT_TRUE(contains(*stats.error, files_.file(0))) << "names the file";
    EXPECT_EQ(lines_of(target), std::vector<std::string>{"precious"});
    EXPECT_TRUE(contains(log_.str(), "1 line(s) lost")) << "logged once, with the count";
}

TEST_F(CaptureWriterTest, ASymlinkedMarkMeansNoDurableStorageAndIsNotFollowed) {
    const auto target = tmp_.file("elsewhere");
    std::ofstream(target) << "precious\n";
    std::filesystem::create_symlink(target, files_.mark());
    CaptureWriter writer(files_, 1001, log_.logger);
    EXPECT_FALSE(writer.reserved()) << "indexes are per-run; the log says so";
    writer.reserve(5000);
    writer.write(capture(1));
    writer.drain();
    EXPECT_FALSE(writer.reserved());
    EXPECT_EQ(writer.stats().written, 1u) << "the lines are still written";
    ASSERT_TRUE(writer.stats().error) << "status keeps saying it, a write succeeding or not";
    EXPECT_TRUE(contains(*writer.stats().error, files_.mark())) << *writer.stats().error;
    EXPECT_TRUE(contains(log_.str(), "no durable storage")) << log_.str();
    EXPECT_EQ(lines_of(target), std::vector<std::string>{"precious"});
}

// Lines lost (here every write fails: the log file is a directory) never
// let an index be given twice: the restart starts at the reservation.
TEST_F(CaptureWriterTest, LostLinesDoNotLetARestartReuseTheirIndexes) {
    std::filesystem::create_directory(files_.file(0));
    {
        CaptureWriter writer(files_, 1 + CaptureWriter::kFirstReservation, log_.logger);
        ASSERT_EQ(writer.reserved(), 1001u);
        for (std::uint64_t i = 1; i <= 5; ++i) {
            writer.write(capture(i));
        }
        writer.drain();
        EXPECT_EQ(writer.stats().dropped, 5u);
    }
    const auto restored = read_captures(files_, 100);
    EXPECT_TRUE(restored.lines.empty());
    EXPECT_EQ(restored.stored_mark, 1001u);
    EXPECT_EQ(restored.next_index, 1001u) << "past every index that may have been given";
}

TEST_F(CaptureWriterTest, ReserveRaisesTheDurableMarkAndFinishSettlesIt) {
    {
        CaptureWriter writer(files_, 1001, log_.logger);
        writer.reserve(900);  // marks only grow
        writer.reserve(2500);
        writer.drain();
        EXPECT_EQ(writer.reserved(), 2500u);
        EXPECT_EQ(read_captures(files_, 10).stored_mark, 2500u) << "on the disk before reserved()";
        writer.finish(1700);  // a clean stop at 1700: the next start goes on from there
    }
    EXPECT_EQ(read_captures(files_, 10).next_index, 1700u);
    EXPECT_EQ(std::filesystem::file_size(files_.mark()), 21u) << "one fixed-size record";
}

// A real disk that fills up (root: a 64 KiB tmpfs): lines are lost, the
// reservation, rewritten in place, still goes through.
TEST_F(CaptureWriterTest, AFullDiskStillTakesTheReservation) {
    if (::geteuid() != 0 ||
        ::mount("tmpfs", files_.dir.c_str(), "tmpfs", 0, "size=64k,mode=0750") != 0) {
        GTEST_SKIP() << "needs root and a tmpfs; LostLinesDoNotLetARestartReuseTheirIndexes "
                        "covers lost lines without it";
    }
    struct Unmount {
        std::string path;
        ~Unmount() { ::umount2(path.c_str(), MNT_DETACH); }
    } unmount{files_.dir};
    CaptureWriter writer(files_, 1001, log_.logger, 4096);
    for (std::uint64_t i = 1; i <= 200; ++i) {
        writer.write(capture(i, 1000));
    }
    writer.drain();
    const auto stats = writer.stats();
    ASSERT_GT(stats.dropped, 0u) << "64 KiB never filled";
    ASSERT_TRUE(stats.error);
    EXPECT_TRUE(contains(*stats.error, "No space left on device")) << *stats.error;
    writer.reserve(3000);
    writer.drain();
    EXPECT_EQ(writer.reserved(), 3000u);
    EXPECT_EQ(read_captures(files_, 10).stored_mark, 3000u);
}

TEST_F(CaptureWriterTest, AReadOnlyDirectoryIsAnErrorAndAWritableOneClearsIt) {
    if (::geteuid() == 0) {
        GTEST_SKIP() << "root writes into a read-only directory; the symlink and directory "
                        "tests cover write errors as root";
    }
    CaptureWriter writer(files_, 1001, log_.logger);
    ::chmod(files_.dir.c_str(), 0555);
    writer.write(capture(1));
    writer.drain();
    ASSERT_TRUE(writer.stats().error);
    EXPECT_TRUE(contains(*writer.stats().error, "Permission denied"));
    ::chmod(files_.dir.c_str(), 0755);
    writer.write(capture(2));
    writer.drain();
    EXPECT_FALSE(writer.stats().error) << "a write that succeeds clears the error";
    EXPECT_EQ(writer.stats().written, 1u);
    EXPECT_EQ(writer.stats().dropped, 1u);
}

// A disk that stalls: the file is a FIFO whose pipe is full and that
// nobody reads, so the thread's write() blocks. write() must still return
// at once, dropping beyond the queue, counted, with the cause in status
// until a line queued after the loss is written.
TEST_F(CaptureWriterTest, AStalledDiskNeverBlocksTheCallerAndDropsBeyondTheQueue) {
    ASSERT_EQ(::mkfifo(files_.file(0).c_str(), 0600), 0);
    const int filler = ::open(files_.file(0).c_str(), O_RDWR | O_NONBLOCK);
    ASSERT_GE(filler, 0);
    const std::string block(4096, 'f');
    while (::write(filler, block.data(), block.size()) > 0) {
    }
    constexpr std::size_t kQueue = 4;
    CaptureWriter writer(files_, 1001, log_.logger, kQueue);
    const auto start = std::chrono::steady_clock::now();
    std::uint64_t sent = 0;
    while (sent < 30) {
        writer.write(capture(++sent, 100));
    }
    // A thread that took its batch late (a slow start, as under ASan) let
    // lines into the queue after a loss: write on until the last write is
    // itself lost, so no line queued after the loss waits (the thread,
    // stuck on the full pipe, takes nothing more, so the queue fills).
    for (;;) {
        const auto dropped = writer.stats().dropped;
        writer.write(capture(++sent, 100));
        if (writer.stats().dropped > dropped) {
            break;
        }
    }
    EXPECT_LT(std::chrono::steady_clock::now() - start, 2s);
    // Held: the batch the thread took (up to kQueue) and the queue.
    EXPECT_GE(writer.stats().dropped, sent - 2 * kQueue);
    EXPECT_EQ(writer.stats().written, 0u);
    ASSERT_TRUE(writer.stats().error);
    EXPECT_TRUE(contains(*writer.stats().error, "queue full")) << *writer.stats().error;
    EXPECT_TRUE(contains(log_.str(), "queue full")) << "the loss is logged";
    {
        FifoReader reader(files_.file(0));  // unstalls it
        writer.drain();
        EXPECT_TRUE(writer.stats().error) << "no line queued after the loss written yet";
        writer.write(capture(++sent, 100));
        writer.drain();
    }
    const auto stats = writer.stats();
    EXPECT_EQ(stats.written + stats.dropped, sent);
    EXPECT_GE(stats.written, 2u);
    EXPECT_FALSE(stats.error) << "a line queued after the loss was written";
    ::close(filler);
}

// Exit on a stalled disk: the writer waits its bound, counts and logs the
// lines not written and leaves the thread behind; the thread, unstalled
// later, touches nothing that was destroyed.
TEST_F(CaptureWriterTest, AStalledDiskDelaysDestructionOnlyByTheBound) {
    ASSERT_EQ(::mkfifo(files_.file(0).c_str(), 0600), 0);
    const auto start = std::chrono::steady_clock::now();
    {
        CaptureWriter writer(files_, 1001, log_.logger, 64, 300ms);
        for (std::uint64_t i = 1; i <= 30; ++i) {
            writer.write(capture(i, 8000));
        }
    }
    const auto took = std::chrono::steady_clock::now() - start;
    EXPECT_LT(took, 5s) << "joined a thread stuck in write()";
    EXPECT_GE(took, 300ms);
    const auto text = log_.str();
    EXPECT_TRUE(contains(text, "line(s) not written")) << text;
    EXPECT_TRUE(contains(text, files_.file(0))) << text;
    FifoReader reader(files_.file(0));  // the thread left behind wakes up and ends
    std::this_thread::sleep_for(100ms);
}

// A flood, as fast as the caller can: a queue large enough loses nothing,
// the lines being fdatasync'd in groups rather than one by one.
TEST_F(CaptureWriterTest, AFloodLosesNothingTheQueueCanHold) {
    constexpr std::uint64_t kLines = 3000;
    {
        CaptureWriter writer(files_, 1001, log_.logger, kLines);
        for (std::uint64_t i = 1; i <= kLines; ++i) {
            writer.write(capture(i, 300));
        }
        writer.drain();
        EXPECT_EQ(writer.stats().written, kLines);
        EXPECT_EQ(writer.stats().dropped, 0u);
    }
    EXPECT_EQ(lines_of(files_.file(0)).size(), kLines);
}

TEST_F(CaptureWriterTest, WritesOneLinePerCaptureMode0640AndStartUpReadsThemBack) {
    const auto old_mask = ::umask(077);  // as the unit's UMask=
    {
        CaptureWriter writer(files_, 1001, log_.logger);
        for (std::uint64_t i = 1; i <= 3; ++i) {
            writer.write(capture(i));
        }
        writer.drain();
        EXPECT_EQ(writer.stats().written, 3u);
        EXPECT_EQ(writer.stats().dropped, 0u);
        EXPECT_FALSE(writer.stats().error);
    }
    ::umask(old_mask);
    struct stat st {};
    ASSERT_EQ(::stat(files_.file(0).c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0640u) << "its group may read it";
    EXPECT_EQ(lines_of(files_.file(0)), (std::vector{capture(1), capture(2), capture(3)}));
    const auto restored = read_captures(files_, 100);
    EXPECT_EQ(restored.lines.size(), 3u);
    EXPECT_EQ(restored.next_index, 1001u) << "the reservation, not past the last line";
    EXPECT_TRUE(restored.problems.empty());
}

TEST_F(CaptureWriterTest, ALineCutShortIsEndedAndSkippedOnRestore) {
    std::ofstream(files_.file(0)) << capture(5) << "\n{\"index\":6,\"ki";  // a crash mid-line
    {
        CaptureWriter writer(files_, 7, log_.logger);
        writer.write(capture(7));
        writer.finish(8);
    }
    const auto restored = read_captures(files_, 100);
    EXPECT_EQ(restored.lines, (std::vector{capture(5), capture(7)}));
    EXPECT_EQ(restored.next_index, 8u);
    ASSERT_EQ(restored.problems.size(), 1u);
    EXPECT_TRUE(contains(restored.problems[0], "1 line(s)")) << restored.problems[0];
}

TEST_F(CaptureWriterTest, RotatesBySizeKeepingNFiles) {
    files_.max_file_bytes = 4096;
    files_.keep_files = 3;
    const std::size_t per_file = 4096 / (capture(1, 400).size() + 1);
    const std::uint64_t total = per_file * 5 + 2;  // more than three files hold
    {
        CaptureWriter writer(files_, 1, log_.logger);
        for (std::uint64_t i = 1; i <= total; ++i) {
            writer.write(capture(i, 400));
            writer.drain();  // the queue is not under test here
        }
        EXPECT_EQ(writer.stats().written, total);
        writer.finish(total + 1);
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

}  // namespace
}  // namespace gport::capture::test
