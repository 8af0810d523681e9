// The shared-memory attitude ring (version 2) and the wake block: layout
// checks, reading what was published, readers that fall behind, a writer
// that rewrites the header after the check, and waking a waiter in another
// process through a memfd mapped read-only.
#include "gport/base/attitude_ring.hpp"

#include <gtest/gtest.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "gport/base/futex.hpp"
#include "gport/base/wake_block.hpp"

namespace gport::base {
namespace {

using namespace std::chrono_literals;

RingSample sample(std::uint64_t seq) {
    RingSample s;
    s.seq = seq;
    s.t = 1763770000.0 + static_cast<double>(seq) / 100;
    s.imu = {0.5, -1.25, static_cast<double>(seq)};
    s.hall = {-19.21, -0.16, 4.66};
    s.has_rates = seq % 2 == 0;
    s.hall_rates = {1.25, -0.5, 0};
    s.imu_rates = {0.12, -2.3, 0};
    return s;
}

void expect_same(const RingSample& a, const RingSample& b) {
    EXPECT_EQ(a.seq, b.seq);
    EXPECT_EQ(a.t, b.t);
    EXPECT_EQ(a.imu, b.imu);
    EXPECT_EQ(a.hall, b.hall);
    EXPECT_EQ(a.has_rates, b.has_rates);
    EXPECT_EQ(a.hall_rates, b.hall_rates);
    EXPECT_EQ(a.imu_rates, b.imu_rates);
}

// Zero-filled, 8-byte-aligned memory for a ring of `slots` slots.
struct Block {
    explicit Block(std::uint32_t slots) : bytes(ring_bytes(slots)), words(bytes / 8 + 1, 0) {}
    void* data() { return words.data(); }
    std::size_t size() const { return bytes; }
    std::size_t bytes;
    std::vector<std::uint64_t> words;
};

TEST(AttitudeRing, AnEmptyRingHasNothingToRead) {
    Block block(8);
    RingWriter writer(block.data(), 8);
    RingReader reader(block.data(), block.size());
    EXPECT_EQ(RingReader::check(block.data(), ring_bytes(8)), std::nullopt);
    EXPECT_EQ(reader.published(), 0U);
    EXPECT_FALSE(reader.latest());
    std::uint64_t cursor = 0;
    std::uint64_t missed = 0;
    EXPECT_FALSE(reader.next(cursor, missed));
    EXPECT_FALSE(reader.closed());
}

TEST(AttitudeRing, ReadsBackEveryFieldOfWhatWasPublished) {
    Block block(8);
    RingWriter writer(block.data(), 8);
    RingReader reader(block.data(), block.size());
    writer.publish(sample(41));
    writer.publish(sample(42));
    ASSERT_TRUE(reader.latest());
    expect_same(*reader.latest(), sample(42));
    expect_same(*reader.read(1), sample(41));
    EXPECT_EQ(static_cast<const RingHeader*>(block.data())->reserved_wake, 0U);  // version 2
}

TEST(AttitudeRing, NextStartsAtTheNewestAndThenTakesEachInTurn) {
    Block block(8);
    RingWriter writer(block.data(), 8);
    RingReader reader(block.data(), block.size());
    for (std::uint64_t i = 1; i <= 3; ++i) {
        writer.publish(sample(i));
    }
    std::uint64_t cursor = 0;
    std::uint64_t missed = 0;
    EXPECT_EQ(reader.next(cursor, missed)->seq, 3U);
    EXPECT_FALSE(reader.next(cursor, missed));
    writer.publish(sample(4));
    writer.publish(sample(5));
    EXPECT_EQ(reader.next(cursor, missed)->seq, 4U);
    EXPECT_EQ(reader.next(cursor, missed)->seq, 5U);
    EXPECT_EQ(missed, 0U);
}

TEST(AttitudeRing, AReaderLappedByTheWriterSkipsAheadAndCountsWhatItMissed) {
    Block block(8);
    RingWriter writer(block.data(), 8);
    RingReader reader(block.data(), block.size());
    writer.publish(sample(1));
    std::uint64_t cursor = 0;
    std::uint64_t missed = 0;
    ASSERT_EQ(reader.next(cursor, missed)->seq, 1U);
    for (std::uint64_t i = 2; i <= 21; ++i) {
        writer.publish(sample(i));
    }
    EXPECT_FALSE(reader.read(2));  // overwritten long ago
    const auto first = reader.next(cursor, missed);
    ASSERT_TRUE(first);
    EXPECT_EQ(first->seq, 21U - 4);  // half a ring behind the newest
    EXPECT_EQ(missed, 17U - 2);      // 2 ... 16
    std::uint64_t taken = 1;
    while (reader.next(cursor, missed)) {
        ++taken;
    }
    EXPECT_EQ(taken + missed, 21U - 1);  // every sample after the first: taken or missed
}

// A reader exactly one ring behind wants the slot the writer fills next. If
// the writer stops half-way through that slot (gportd killed), the reader
// must skip ahead rather than retry the torn slot for ever.
TEST(AttitudeRing, AWriterStoppedInsideTheSlotANearlyLappedReaderWantsDoesNotHangIt) {
    Block block(8);
    RingWriter writer(block.data(), 8);
    RingReader reader(block.data(), block.size());
    writer.publish(sample(1));
    std::uint64_t cursor = 0;
    std::uint64_t missed = 0;
    ASSERT_EQ(reader.next(cursor, missed)->seq, 1U);
    for (std::uint64_t i = 2; i <= 9; ++i) {
        writer.publish(sample(i));
    }
    // Sample 10 goes where sample 2 is: begun (odd seq), never finished.
    auto* slots = ring_detail::slots(static_cast<RingHeader*>(block.data()));
    slots[(10 - 1) % 8].seq.store(2 * 10 - 1);
    const auto taken = reader.next(cursor, missed);
    ASSERT_TRUE(taken);
    EXPECT_EQ(taken->seq, 9U - 4);  // half a ring behind the newest
    EXPECT_EQ(missed, 3U);          // 2, 3 and 4
}

TEST(AttitudeRing, CheckNamesWhatIsWrongWithABlock) {
    Block block(8);
    RingWriter writer(block.data(), 8);
    EXPECT_EQ(RingReader::check(block.data(), ring_bytes(8)), std::nullopt);
    EXPECT_EQ(RingReader::check(block.data(), 10), "the block is smaller than a ring header");
    EXPECT_EQ(RingReader::check(block.data(), ring_bytes(8) - 1),
              "the block is smaller than its ring");
    EXPECT_EQ(RingReader::check(block.data(), ring_bytes(8) + 128),
              "the block is larger than its ring");
    auto* header = static_cast<RingHeader*>(block.data());
    header->version = 1;  // a version 1 reader would sleep on a word nobody bumps any more
    EXPECT_EQ(RingReader::check(block.data(), ring_bytes(8)),
              "attitude ring version 1 is not supported (2 is)");
    header->version = kRingVersion;
    header->slot_count = 6;
    EXPECT_EQ(RingReader::check(block.data(), ring_bytes(8)),
              "attitude ring slot count 6 is not a power of two from 1 to 65536");
    header->slot_count = 1U << 31;
    EXPECT_EQ(RingReader::check(block.data(), ring_bytes(8)),
              "attitude ring slot count 2147483648 is not a power of two from 1 to 65536");
    header->magic = 0;
    EXPECT_EQ(RingReader::check(block.data(), ring_bytes(8)), "not an attitude ring (bad magic)");
}

// A hostile writer that keeps a writable mapping rewrites slot_count after
// the reader checked it: 0 made the modulo divide by zero (SIGFPE), 2^31
// sent the index far outside the mapping (SIGSEGV). The reader uses the
// count it derived from the mapping's size, once.
TEST(AttitudeRing, ARewrittenSlotCountAfterTheCheckChangesNothingForTheReader) {
    Block block(8);
    RingWriter writer(block.data(), 8);
    ASSERT_EQ(RingReader::check(block.data(), block.size()), std::nullopt);
    RingReader reader(block.data(), block.size());
    for (std::uint64_t i = 1; i <= 5; ++i) {
        writer.publish(sample(i));
    }
    auto* header = static_cast<RingHeader*>(block.data());
    for (const std::uint32_t hostile : {0U, 1U << 31, 3U, 0xffffffffU}) {
        header->slot_count = hostile;
        EXPECT_EQ(reader.slot_count(), 8U);
        expect_same(*reader.latest(), sample(5));
        std::uint64_t cursor = 1;
        std::uint64_t missed = 0;
        EXPECT_EQ(reader.next(cursor, missed)->seq, 2U);
    }
    header->published.store(1ULL << 62);  // and `published` far beyond the ring: nothing, no crash
    EXPECT_FALSE(reader.latest());
    std::array<std::uint64_t, kRingSampleWords> words{};
    EXPECT_FALSE(ring_read_words(block.data(), 8, 1ULL << 62, words));
    EXPECT_FALSE(ring_read_words(block.data(), 0, 1, words));
}

TEST(AttitudeRing, CloseIsSeenByReaders) {
    Block block(4);
    RingWriter writer(block.data(), 4);
    RingReader reader(block.data(), block.size());
    writer.close();
    EXPECT_TRUE(reader.closed());
}

TEST(WakeBlock, AFormattedBlockPassesItsCheckAndCheckNamesWhatIsWrong) {
    alignas(64) std::array<std::byte, kWakeBlockBytes> memory{};
    format_wake_block(memory.data());
    EXPECT_EQ(check_wake_block(memory.data(), kWakeBlockBytes), std::nullopt);
    EXPECT_EQ(wake_word(memory.data()).load(), 0U);
    EXPECT_EQ(check_wake_block(memory.data(), 4096), "the wake block is 4096 bytes, not 64");
    auto* block = static_cast<WakeBlock*>(static_cast<void*>(memory.data()));
    block->size = 128;
    EXPECT_EQ(check_wake_block(memory.data(), kWakeBlockBytes),
              "the wake block's header gives size 128, not 64");
    block->version = 7;
    EXPECT_EQ(check_wake_block(memory.data(), kWakeBlockBytes),
              "wake block version 7 is not supported (1 is)");
    block->magic = kRingMagic;
    EXPECT_EQ(check_wake_block(memory.data(), kWakeBlockBytes),
              "not an attitude channel wake block (bad magic)");
}

TEST(AttitudeRing, AWaiterInAnotherProcessIsWokenThroughReadOnlyMappings) {
    const int fd = memfd_create("attitude-ring-test", MFD_CLOEXEC);
    const int wake_fd = memfd_create("attitude-wake-test", MFD_CLOEXEC);
    ASSERT_GE(fd, 0);
    ASSERT_GE(wake_fd, 0);
    const std::size_t size = ring_bytes(16);
    ASSERT_EQ(ftruncate(fd, static_cast<off_t>(size)), 0);
    ASSERT_EQ(ftruncate(wake_fd, static_cast<off_t>(kWakeBlockBytes)), 0);
    void* rw = mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    void* wake_rw = mmap(nullptr, kWakeBlockBytes, PROT_READ | PROT_WRITE, MAP_SHARED, wake_fd, 0);
    ASSERT_NE(rw, MAP_FAILED);
    ASSERT_NE(wake_rw, MAP_FAILED);
    RingWriter writer(rw, 16);
    WakeBlock* wake = format_wake_block(wake_rw);

    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        const void* ro = mmap(nullptr, size, PROT_READ, MAP_SHARED, fd, 0);
        const void* wake_ro = mmap(nullptr, kWakeBlockBytes, PROT_READ, MAP_SHARED, wake_fd, 0);
        if (ro == MAP_FAILED || wake_ro == MAP_FAILED || RingReader::check(ro, size) ||
            check_wake_block(wake_ro, kWakeBlockBytes)) {
            _exit(2);
        }
        RingReader reader(ro, size);
        const auto& word = wake_word(wake_ro);
        std::uint64_t cursor = 0;
        std::uint64_t missed = 0;
        for (int waits = 0; waits < 500; ++waits) {
            const auto seen = word.load(std::memory_order_acquire);
            if (auto s = reader.next(cursor, missed); s && s->seq == 7) {
                _exit(0);
            }
            futex_wait(word, seen, 100ms);
        }
        _exit(3);
    }
    for (std::uint64_t i = 1; i <= 7; ++i) {
        writer.publish(sample(i));
        wake->wake.fetch_add(1, std::memory_order_release);
        futex_wake(wake->wake, 1);
    }
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    EXPECT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0);
    munmap(rw, size);
    munmap(wake_rw, kWakeBlockBytes);
    close(fd);
    close(wake_fd);
}

}  // namespace
}  // namespace gport::base
