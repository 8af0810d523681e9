// The shared-memory attitude channel's layout: a seqlock ring of the latest
// attitude samples in one memory block that gportd writes and any number of
// clients map read-only (docs/api.md, "Shared-memory attitude channel").
//
// The block is a RingHeader followed by slot_count RingSlots. Every field a
// reader looks at is a lock-free, address-free atomic, so the block can be
// mapped by several processes at once. Sample n (1, 2, ...) lives in slot
// (n - 1) % slot_count; its slot's `seq` is 2n - 1 while it is written and
// 2n once it is complete, so a reader knows both that a slot is stable and
// which sample it holds. A reader that falls more than slot_count samples
// behind sees a newer sample, never a torn one: it cannot slow the writer.
//
// Nobody waits on the ring itself: gportd gives each connection that opens
// the channel a wake block of its own (wake_block.hpp) and bumps and wakes
// every connection's word after each sample, so no reader can steal, or set
// the cost of, another connection's wakes (docs/api.md).
//
// Version 2: as version 1, except that the header's u32 at offset 24 (the
// futex word of version 1) is reserved and always 0. A change of layout
// changes kRingVersion; readers refuse a version they do not know, so a
// version 1 reader never sleeps on a word nobody bumps any more.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>

namespace gport::base {

inline constexpr std::uint32_t kRingMagic = 0x52415047;  // "GPAR" in little-endian memory
inline constexpr std::uint32_t kRingVersion = 2;
// The most slots a reader accepts: far above gportd's 64, and a bound on
// what a block from a hostile server may make a reader map.
inline constexpr std::uint32_t kRingMaxSlots = 1U << 16;
inline constexpr std::uint32_t kRingFlagClosed = 1;  // the writer stopped publishing

// One attitude sample as the channel carries it: the JSON notification's
// fields, in the same units (degrees, degrees/second, Unix seconds).
struct RingSample {
    std::uint64_t seq = 0;               // gportd's sample number (the notification's "seq")
    double t = 0;                        // receive time, Unix seconds
    std::array<double, 3> imu{};         // roll, pitch, yaw
    std::array<double, 3> hall{};        // roll, pitch, yaw
    bool has_rates = false;              // the gimbal sent the 24-byte form
    std::array<double, 3> hall_rates{};  // roll, pitch, yaw
    std::array<double, 3> imu_rates{};   // x, y, z
};

inline constexpr std::size_t kRingSampleWords = 15;

struct RingSlot {
    std::atomic<std::uint64_t> seq;  // 2n - 1 while sample n is written, 2n once complete
    std::array<std::atomic<std::uint64_t>, kRingSampleWords> words;
};

struct RingHeader {
    std::uint32_t magic;
    std::uint32_t version;
    std::uint32_t header_size;         // sizeof(RingHeader): where slot 0 starts
    std::uint32_t slot_size;           // sizeof(RingSlot)
    std::uint32_t slot_count;          // a power of two
    std::atomic<std::uint32_t> flags;  // kRingFlagClosed
    std::uint32_t reserved_wake;       // version 1's futex word: always 0 in version 2
    std::uint32_t reserved0;
    std::atomic<std::uint64_t> published;  // samples published so far (n of the newest)
    std::array<std::uint64_t, 3> reserved;
};

static_assert(std::atomic<std::uint64_t>::is_always_lock_free);
static_assert(std::atomic<std::uint32_t>::is_always_lock_free);
static_assert(sizeof(RingHeader) == 64);
static_assert(sizeof(RingSlot) == 128);
static_assert(offsetof(RingHeader, slot_count) == 16);
static_assert(offsetof(RingHeader, flags) == 20);
static_assert(offsetof(RingHeader, reserved_wake) == 24);
static_assert(offsetof(RingHeader, published) == 32);

constexpr std::size_t ring_bytes(std::uint32_t slot_count) {
    return sizeof(RingHeader) + std::size_t{slot_count} * sizeof(RingSlot);
}

namespace ring_detail {

// Slot 0 starts right after the header (header + 1): a cast between two
// types of the same alignment, never from a byte pointer (which 32-bit ARM's
// -Wcast-align rightly questions).
static_assert(alignof(RingHeader) >= alignof(RingSlot));
static_assert(sizeof(RingHeader) % alignof(RingSlot) == 0);

inline RingSlot* slots(RingHeader* header) {
    return reinterpret_cast<RingSlot*>(header + 1);
}
inline const RingSlot* slots(const RingHeader* header) {
    return reinterpret_cast<const RingSlot*>(header + 1);
}

inline std::array<std::uint64_t, kRingSampleWords> to_words(const RingSample& s) {
    const auto d = [](double v) { return std::bit_cast<std::uint64_t>(v); };
    return {s.seq,
            d(s.t),
            d(s.imu[0]),
            d(s.imu[1]),
            d(s.imu[2]),
            d(s.hall[0]),
            d(s.hall[1]),
            d(s.hall[2]),
            s.has_rates ? 1U : 0U,
            d(s.hall_rates[0]),
            d(s.hall_rates[1]),
            d(s.hall_rates[2]),
            d(s.imu_rates[0]),
            d(s.imu_rates[1]),
            d(s.imu_rates[2])};
}

inline RingSample from_words(const std::array<std::uint64_t, kRingSampleWords>& w) {
    const auto d = [](std::uint64_t v) { return std::bit_cast<double>(v); };
    return RingSample{w[0],
                      d(w[1]),
                      {d(w[2]), d(w[3]), d(w[4])},
                      {d(w[5]), d(w[6]), d(w[7])},
                      w[8] != 0,
                      {d(w[9]), d(w[10]), d(w[11])},
                      {d(w[12]), d(w[13]), d(w[14])}};
}

}  // namespace ring_detail

// The one writer (gportd). `memory` is ring_bytes(slot_count) bytes of
// zero-filled, 64-byte-aligned shared memory that it formats.
class RingWriter {
  public:
    RingWriter(void* memory, std::uint32_t slot_count)
        : header_(static_cast<RingHeader*>(memory)), slot_count_(slot_count) {
        header_->magic = kRingMagic;
        header_->version = kRingVersion;
        header_->header_size = sizeof(RingHeader);
        header_->slot_size = sizeof(RingSlot);
        header_->slot_count = slot_count;
        header_->flags.store(0, std::memory_order_relaxed);
        header_->reserved_wake = 0;
        header_->published.store(0, std::memory_order_release);
    }

    // Writes the next sample; the caller then bumps and wakes each reader's
    // wake block (wake_block.hpp).
    void publish(const RingSample& sample) {
        const std::uint64_t n = header_->published.load(std::memory_order_relaxed) + 1;
        RingSlot& slot = ring_detail::slots(header_)[(n - 1) % slot_count_];
        slot.seq.store(2 * n - 1, std::memory_order_relaxed);
        std::atomic_thread_fence(std::memory_order_release);
        const auto words = ring_detail::to_words(sample);
        for (std::size_t i = 0; i < kRingSampleWords; ++i) {
            slot.words[i].store(words[i], std::memory_order_relaxed);
        }
        slot.seq.store(2 * n, std::memory_order_release);
        header_->published.store(n, std::memory_order_release);
    }

    // No more samples will come (gportd is stopping); readers see closed()
    // once the caller has bumped and woken their wake blocks.
    void close() { header_->flags.fetch_or(kRingFlagClosed, std::memory_order_release); }

    std::uint64_t published() const { return header_->published.load(std::memory_order_acquire); }

  private:
    RingHeader* header_;
    std::uint32_t slot_count_;
};

// The seqlock read of sample n from a block of `slot_count` slots (the
// count the reader checked, never re-read from shared memory): its words if
// the sample is still in the ring and complete. The C entry point
// gport_ring_read (libgport-client) is this function.
inline bool ring_read_words(const void* memory, std::uint32_t slot_count, std::uint64_t n,
                            std::array<std::uint64_t, kRingSampleWords>& words) {
    if (n == 0 || slot_count == 0) {
        return false;
    }
    const auto* header = static_cast<const RingHeader*>(memory);
    const RingSlot& slot = ring_detail::slots(header)[(n - 1) % slot_count];
    const std::uint64_t before = slot.seq.load(std::memory_order_acquire);
    if (before != 2 * n) {
        return false;  // being written, overwritten, or not written yet
    }
    for (std::size_t i = 0; i < kRingSampleWords; ++i) {
        words[i] = slot.words[i].load(std::memory_order_relaxed);
    }
    std::atomic_thread_fence(std::memory_order_acquire);
    return slot.seq.load(std::memory_order_relaxed) == before;  // else overwritten while read
}

// A reader over a mapping of the whole block (read-only is enough).
class RingReader {
  public:
    // Checks the header against the mapping's size, which must be exactly
    // ring_bytes(slot_count) for the slot count the header gives; the error
    // names what is wrong. A reader is only made from a block that passed.
    static std::optional<std::string> check(const void* memory, std::size_t size) {
        if (size < sizeof(RingHeader)) {
            return "the block is smaller than a ring header";
        }
        // One copy of the fields checked: a writer changing them meanwhile
        // cannot make two looks disagree.
        struct {
            std::uint32_t magic, version, header_size, slot_size, slot_count;
        } h{};
        std::memcpy(&h, memory, sizeof(h));
        if (h.magic != kRingMagic) {
            return "not an attitude ring (bad magic)";
        }
        if (h.version != kRingVersion) {
            return "attitude ring version " + std::to_string(h.version) + " is not supported (" +
                   std::to_string(kRingVersion) + " is)";
        }
        if (h.header_size != sizeof(RingHeader) || h.slot_size != sizeof(RingSlot)) {
            return "attitude ring header or slot size does not match version " +
                   std::to_string(kRingVersion);
        }
        if (h.slot_count == 0 || (h.slot_count & (h.slot_count - 1)) != 0 ||
            h.slot_count > kRingMaxSlots) {
            return "attitude ring slot count " + std::to_string(h.slot_count) +
                   " is not a power of two from 1 to " + std::to_string(kRingMaxSlots);
        }
        if (size < ring_bytes(h.slot_count)) {
            return "the block is smaller than its ring";
        }
        if (size != ring_bytes(h.slot_count)) {
            return "the block is larger than its ring";
        }
        return std::nullopt;
    }

    // The slot count a block of `size` bytes holds (size as check() passed it).
    static std::uint32_t slots_in(std::size_t size) {
        return size < sizeof(RingHeader)
                   ? 0
                   : static_cast<std::uint32_t>((size - sizeof(RingHeader)) / sizeof(RingSlot));
    }

    // `size`: the mapping's size, which check() passed. The slot count is
    // taken from it, once: whatever the block's header says later, every
    // index stays inside the mapping.
    RingReader(const void* memory, std::size_t size)
        : header_(static_cast<const RingHeader*>(memory)), slot_count_(slots_in(size)) {}

    std::uint64_t published() const { return header_->published.load(std::memory_order_acquire); }
    std::uint32_t slot_count() const { return slot_count_; }
    bool closed() const {
        return (header_->flags.load(std::memory_order_acquire) & kRingFlagClosed) != 0;
    }

    // Sample n, if it is still in the ring and complete.
    std::optional<RingSample> read(std::uint64_t n) const {
        std::array<std::uint64_t, kRingSampleWords> words{};
        if (!ring_read_words(header_, slot_count_, n, words)) {
            return std::nullopt;
        }
        return ring_detail::from_words(words);
    }

    std::optional<RingSample> latest() const {
        for (int attempt = 0; attempt < 4; ++attempt) {  // the writer may lap one read
            if (auto sample = read(published())) {
                return sample;
            }
        }
        return std::nullopt;
    }

    // The sample after `cursor` (the ring index of the last one taken, 0 at
    // first), or nothing when none is newer. A reader that starts at 0 begins
    // with the newest sample. One that fell more than slot_count behind, or
    // whose next sample was overwritten while it looked, jumps to half a ring
    // behind the newest; every sample it skips is added to `missed`. Bounded:
    // a writer stopped in the middle of a slot never makes it spin.
    std::optional<RingSample> next(std::uint64_t& cursor, std::uint64_t& missed) const {
        bool lapped = false;
        for (int attempt = 0; attempt < 4; ++attempt) {
            const std::uint64_t newest = published();
            if (newest <= cursor) {
                return std::nullopt;
            }
            std::uint64_t want = cursor + 1;
            if (cursor == 0) {
                want = newest;
            } else if (lapped || newest - cursor > slot_count_) {
                want = std::max(cursor + 1, newest - slot_count_ / 2);
            }
            if (auto sample = read(want)) {
                missed += cursor == 0 ? 0 : want - cursor - 1;
                cursor = want;
                return sample;
            }
            // Overwritten between published() and read(), or being
            // overwritten: the writer lapped this reader.
            lapped = true;
        }
        return std::nullopt;
    }

  private:
    const RingHeader* header_;
    std::uint32_t slot_count_;
};

}  // namespace gport::base
