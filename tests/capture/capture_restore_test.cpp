// The capture log's start-up: the state directory checked and the
// kept files read back, bounded and in index order whatever they hold (a
// crafted file first).
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "capture_test_files.hpp"
#include "gport/capture/capture_writer.hpp"

namespace gport::capture::test {
namespace {

bool has_problem(const RestoredCaptures& restored, const std::string& part) {
    for (const auto& problem : restored.problems) {
        if (problem.find(part) != std::string::npos) {
            return true;
        }
    }
    return false;
}

long peak_rss_kib() {
    rusage usage{};
    ::getrusage(RUSAGE_SELF, &usage);
    return usage.ru_maxrss;
}

using CaptureRestoreTest = CaptureFilesTest;

// A 64 MiB line: skipped as it streams past, never held (nor parsed).
TEST_F(CaptureRestoreTest, AHugeLineIsSkippedWithoutHoldingIt) {
    files_.max_file_bytes = 128u << 20;
    {
        std::ofstream out(files_.file(0));
        out << capture(1) << "\n{\"index\":2,\"pad\":\"";
        const std::string block(1 << 20, 'x');
        for (int i = 0; i < 64; ++i) {
            out << block;
        }
        out << "\"}\n" << capture(3) << '\n';
    }
    const auto rss_before = peak_rss_kib();
    const auto start = std::chrono::steady_clock::now();
    const auto restored = read_captures(files_, 100);
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(20));
    EXPECT_LT(peak_rss_kib() - rss_before, 32 * 1024) << "KiB more at peak: the line was held";
    EXPECT_EQ(restored.lines, (std::vector{capture(1), capture(3)}));
    EXPECT_TRUE(has_problem(restored, "1 line(s) skipped (1 longer than 16384 bytes)"));
}

// Nested 100,000 deep (too long, too) and 5,000 deep within the line limit:
// refused before the parser, which recurses once per level.
TEST_F(CaptureRestoreTest, DeepNestingIsSkippedBeforeParsing) {
    const auto nested = [](std::size_t depth) {
        return "{\"index\":2,\"meta\":" + std::string(depth, '[') + std::string(depth, ']') + "}";
    };
    write_file(0, {capture(1), nested(100000), nested(5000), capture(3)});
    const auto restored = read_captures(files_, 100);
    EXPECT_EQ(restored.lines, (std::vector{capture(1), capture(3)}));
    EXPECT_TRUE(has_problem(restored, "1 nested deeper than 64")) << restored.problems[0];
    EXPECT_TRUE(has_problem(restored, "1 longer than 16384 bytes"));
}

// Indexes a JSON reader cannot hold exactly, or that would wrap, or none.
TEST_F(CaptureRestoreTest, OnlyJsonSafeIndexesAreAccepted) {
    const auto max = std::numeric_limits<std::uint64_t>::max();
    write_file(0, {capture(7), capture(0), capture(kMaxCaptureIndex + 1), capture(max - 1),
                   capture(max), R"({"index":-1})", R"({"index":1.5})"});
    const auto restored = read_captures(files_, 100);
    EXPECT_EQ(restored.lines, std::vector{capture(7)});
    EXPECT_EQ(restored.next_index, 8u) << "nothing wraps to 0 or 1";
    EXPECT_TRUE(has_problem(restored, "4 an index outside 1..9007199254740991"));
    EXPECT_TRUE(has_problem(restored, "2 not a capture"));
}

TEST_F(CaptureRestoreTest, TheHighestJsonSafeIndexIsKept) {
    write_file(0, {capture(kMaxCaptureIndex)});
    const auto restored = read_captures(files_, 100);
    EXPECT_EQ(restored.lines.size(), 1u);
    EXPECT_EQ(restored.next_index, kMaxCaptureIndex + 1);
}

// Lines out of order, across files and repeated: sorted by index, the
// repeat dropped, the newest `keep` kept whatever the order.
TEST_F(CaptureRestoreTest, LinesAreSortedByIndexAndRepeatsDropped) {
    write_file(1, {capture(5), capture(9), capture(7)});
    write_file(0, {capture(3), capture(9), capture(8)});
    const auto all = read_captures(files_, 100);
    EXPECT_EQ(all.lines, (std::vector{capture(3), capture(5), capture(7), capture(8), capture(9)}));
    EXPECT_EQ(all.next_index, 10u);
    EXPECT_TRUE(has_problem(all, "1 an index read already"));
    const auto newest = read_captures(files_, 3);
    EXPECT_EQ(newest.lines, (std::vector{capture(7), capture(8), capture(9)}));
}

// A file larger than gportd ever writes: only its tail is read.
TEST_F(CaptureRestoreTest, AnOversizedFileIsReadOnlyForItsLastMaxFileBytes) {
    files_.max_file_bytes = 4096;
    std::vector<std::string> lines;
    for (std::uint64_t i = 1; i <= 200; ++i) {
        lines.push_back(capture(i, 100));
    }
    write_file(0, lines);
    const auto restored = read_captures(files_, 1000);
    EXPECT_EQ(restored.next_index, 201u);
    EXPECT_LT(restored.lines.size(), 4096u / 100);
    EXPECT_EQ(restored.lines.back(), capture(200, 100));
    EXPECT_TRUE(has_problem(restored, "more than captures.max_file_bytes"));
    EXPECT_FALSE(has_problem(restored, "skipped")) << "the partial first line is not a problem";
}

TEST_F(CaptureRestoreTest, AMarkThatIsNotARecordIsIgnoredAndNamed) {
    write_file(0, {capture(4)});
    std::ofstream(files_.mark()) << "18446744073709551615\n";  // past 2^53
    auto restored = read_captures(files_, 100);
    EXPECT_FALSE(restored.stored_mark);
    EXPECT_EQ(restored.next_index, 5u);
    EXPECT_TRUE(has_problem(restored, "not an index reservation"));
    std::ofstream(files_.mark()) << "garbage";
    EXPECT_FALSE(read_captures(files_, 100).stored_mark);
    std::ofstream(files_.mark()) << "00000000000000002000\n";
    restored = read_captures(files_, 100);
    EXPECT_EQ(restored.stored_mark, 2000u);
    EXPECT_EQ(restored.next_index, 2000u);
}

TEST_F(CaptureRestoreTest, SymlinksAndDevicesAreNotRead) {
    std::filesystem::create_symlink("/dev/zero", files_.file(0));
    std::filesystem::create_symlink("/dev/zero", files_.mark());
    const auto restored = read_captures(files_, 100);  // /dev/zero would read forever
    EXPECT_EQ(restored.next_index, 1u);
    EXPECT_TRUE(has_problem(restored, "symbolic link"));
    EXPECT_EQ(restored.problems.size(), 2u);
}

// The directory: gportd's to write alone.
TEST_F(CaptureRestoreTest, ADirectoryOthersMayWriteIsRefusedNamingTheFix) {
    ASSERT_EQ(::chmod(files_.dir.c_str(), 0777), 0);
    auto refused = check_capture_dir(files_.dir);
    ASSERT_TRUE(refused);
    EXPECT_NE(refused->find(files_.dir), std::string::npos) << *refused;
    EXPECT_NE(refused->find("anyone"), std::string::npos) << *refused;
    EXPECT_NE(refused->find("chmod go-w"), std::string::npos) << *refused;
    ASSERT_EQ(::chmod(files_.dir.c_str(), 0770), 0);
    refused = check_capture_dir(files_.dir);
    ASSERT_TRUE(refused);
    EXPECT_NE(refused->find("its group"), std::string::npos) << *refused;
    ASSERT_EQ(::chmod(files_.dir.c_str(), 0750), 0);
    EXPECT_FALSE(check_capture_dir(files_.dir));
    ASSERT_EQ(::chmod(files_.dir.c_str(), 0755), 0);
    EXPECT_FALSE(check_capture_dir(files_.dir)) << "others may read; only writing is refused";
}

TEST_F(CaptureRestoreTest, ADirectoryOfAnotherUserIsRefused) {
    if (::geteuid() != 0) {
        GTEST_SKIP() << "giving a directory away needs root";
    }
    ASSERT_EQ(::chown(files_.dir.c_str(), 12345, 12345), 0);
    const auto refused = check_capture_dir(files_.dir);
    ASSERT_TRUE(refused);
    EXPECT_NE(refused->find("belongs to uid 12345"), std::string::npos) << *refused;
}

// A link another user owns in a sticky, world-writable directory (/tmp)
// is theirs to repoint: refused, though its target passes every check.
TEST_F(CaptureRestoreTest, AnotherUsersLinkInAStickyDirectoryIsNotFollowed) {
    if (::geteuid() != 0) {
        GTEST_SKIP() << "a link of another user needs root to make";
    }
    const auto sticky = tmp_.file("sticky");
    ASSERT_EQ(::mkdir(sticky.c_str(), 01777), 0);
    ASSERT_EQ(::chmod(sticky.c_str(), 01777), 0);  // past the umask
    const auto link = sticky + "/state";
    ASSERT_EQ(::symlink(files_.dir.c_str(), link.c_str()), 0);
    ASSERT_EQ(::lchown(link.c_str(), 12345, 12345), 0);
    auto refused = check_capture_dir(link);
    ASSERT_TRUE(refused);
    EXPECT_NE(refused->find("symbolic link of uid 12345"), std::string::npos) << *refused;
    EXPECT_NE(refused->find("not followed"), std::string::npos) << *refused;
    // Ours, or in a directory only its owner writes: followed, as before.
    ASSERT_EQ(::lchown(link.c_str(), 0, 0), 0);
    EXPECT_FALSE(check_capture_dir(link));
    ASSERT_EQ(::lchown(link.c_str(), 12345, 12345), 0);
    ASSERT_EQ(::chmod(sticky.c_str(), 0755), 0);
    EXPECT_FALSE(check_capture_dir(link));
}

TEST_F(CaptureRestoreTest, AMissingDirectoryIsCreatedForGportdAlone) {
    const auto dir = tmp_.file("new");
    EXPECT_FALSE(check_capture_dir(dir));
    struct stat st {};
    ASSERT_EQ(::stat(dir.c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0022, 0u);
    std::ofstream(tmp_.file("file")) << "x";
    EXPECT_TRUE(check_capture_dir(tmp_.file("file")));
}

}  // namespace
}  // namespace gport::capture::test
