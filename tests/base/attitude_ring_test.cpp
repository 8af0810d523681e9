// The shared-memory attitude ring: layout checks, reading what was
// published, readers that fall behind, and waking a waiter in another
// process through a memfd mapped read-only.
#include "gport/base/attitude_ring.hpp"

#include <gtest/gtest.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "gport/base/futex.hpp"

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
    explicit Block(std::uint32_t slots) : words(ring_bytes(slots) / 8 + 1, 0) {}
    void* data() { return words.data(); }
    std::vector<std::uint64_t> words;
};

TEST(AttitudeRing, AnEmptyRingHasNothingToRead) {
    Block block(8);
    RingWriter writer(block.data(), 8);
    RingReader reader(block.data());
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
    RingReader reader(block.data());
    writer.publish(sample(41));
    writer.publish(sample(42));
    ASSERT_TRUE(reader.latest());
    expect_same(*reader.latest(), sample(42));
    expect_same(*reader.read(1), sample(41));
    EXPECT_EQ(reader.wake_word().load(), 2U);
}

TEST(AttitudeRing, NextStartsAtTheNewestAndThenTakesEachInTurn) {
    Block block(8);
    RingWriter writer(block.data(), 8);
    RingReader reader(block.data());
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
    RingReader reader(block.data());
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
    RingReader reader(block.data());
    writer.publish(sample(1));
    std::uint64_t cursor = 0;
    std::uint64_t missed = 0;
    ASSERT_EQ(reader.next(cursor, missed)->seq, 1U);
    for (std::uint64_t i = 2; i <= 9; ++i) {
        writer.publish(sample(i));
    }
    // Sample 10 goes where sample 2 is: begun (odd seq), never finished.
    auto* slots =
        reinterpret_cast<RingSlot*>(static_cast<std::byte*>(block.data()) + sizeof(RingHeader));
    slots[(10 - 1) % 8].seq.store(2 * 10 - 1);
    const auto taken = reader.next(cursor, missed);
    ASSERT_TRUE(taken);
    EXPECT_EQ(taken->seq, 9U - 4);  // half a ring behind the newest
    EXPECT_EQ(missed, 3U);          // 2, 3 and 4
}

TEST(AttitudeRing, CheckNamesWhatIsWrongWithABlock) {
    Block block(8);
    RingWriter writer(block.data(), 8);
    EXPECT_EQ(RingReader::check(block.data(), 10), "the block is smaller than a ring header");
    EXPECT_EQ(RingReader::check(block.data(), ring_bytes(8) - 1),
              "the block is smaller than its ring");
    auto* header = static_cast<RingHeader*>(block.data());
    header->version = 2;
    EXPECT_EQ(RingReader::check(block.data(), ring_bytes(8)),
              "attitude ring version 2 is not supported (1 is)");
    header->version = kRingVersion;
    header->slot_count = 6;
    EXPECT_EQ(RingReader::check(block.data(), ring_bytes(8)),
              "attitude ring slot count is not a power of two");
    header->magic = 0;
    EXPECT_EQ(RingReader::check(block.data(), ring_bytes(8)), "not an attitude ring (bad magic)");
}

TEST(AttitudeRing, CloseIsSeenByReaders) {
    Block block(4);
    RingWriter writer(block.data(), 4);
    RingReader reader(block.data());
    const auto before = reader.wake_word().load();
    writer.close();
    EXPECT_TRUE(reader.closed());
    EXPECT_NE(reader.wake_word().load(), before);
}

TEST(AttitudeRing, AWaiterInAnotherProcessIsWokenThroughAReadOnlyMapping) {
    const int fd = memfd_create("attitude-ring-test", MFD_CLOEXEC);
    ASSERT_GE(fd, 0);
    const std::size_t size = ring_bytes(16);
    ASSERT_EQ(ftruncate(fd, static_cast<off_t>(size)), 0);
    void* rw = mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    ASSERT_NE(rw, MAP_FAILED);
    RingWriter writer(rw, 16);

    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        const void* ro = mmap(nullptr, size, PROT_READ, MAP_SHARED, fd, 0);
        if (ro == MAP_FAILED || RingReader::check(ro, size)) {
            _exit(2);
        }
        RingReader reader(ro);
        std::uint64_t cursor = 0;
        std::uint64_t missed = 0;
        for (int waits = 0; waits < 500; ++waits) {
            const auto seen = reader.wake_word().load(std::memory_order_acquire);
            if (auto s = reader.next(cursor, missed); s && s->seq == 7) {
                _exit(0);
            }
            futex_wait(reader.wake_word(), seen, 100ms);
        }
        _exit(3);
    }
    for (std::uint64_t i = 1; i <= 7; ++i) {
        writer.publish(sample(i));
        futex_wake_all(writer.wake_word());
    }
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    EXPECT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0);
    munmap(rw, size);
    close(fd);
}

TEST(AttitudeRing, FutexWaitReturnsAtOnceWhenTheWordAlreadyChanged) {
    std::atomic<std::uint32_t> word{5};
    EXPECT_EQ(futex_wait(word, 4, 1s), FutexWait::kChanged);
    EXPECT_EQ(futex_wait(word, 5, 1ms), FutexWait::kTimedOut);
}

}  // namespace
}  // namespace gport::base
