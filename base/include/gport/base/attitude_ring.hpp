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
// The writer bumps `wake` after every sample (and when it closes the
// channel), and then wakes every futex waiter on that word (base/futex.hpp).
//
// Version 1. A change of layout changes kRingVersion; readers refuse a
// version they do not know.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

namespace gport::base {

inline constexpr std::uint32_t kRingMagic = 0x52415047;  // "GPAR" in little-endian memory
inline constexpr std::uint32_t kRingVersion = 1;
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
    std::atomic<std::uint32_t> wake;   // the futex word: bumped per sample and on close
    std::uint32_t reserved0;
    std::atomic<std::uint64_t> published;  // samples published so far (n of the newest)
    std::array<std::uint64_t, 3> reserved;
};

static_assert(std::atomic<std::uint64_t>::is_always_lock_free);
static_assert(std::atomic<std::uint32_t>::is_always_lock_free);
static_assert(sizeof(RingHeader) == 64);
static_assert(sizeof(RingSlot) == 128);

constexpr std::size_t ring_bytes(std::uint32_t slot_count) {
    return sizeof(RingHeader) + std::size_t{slot_count} * sizeof(RingSlot);
}

namespace ring_detail {

inline RingSlot* slots(RingHeader* header) {
    return reinterpret_cast<RingSlot*>(reinterpret_cast<std::byte*>(header) + sizeof(RingHeader));
}
inline const RingSlot* slots(const RingHeader* header) {
    return reinterpret_cast<const RingSlot*>(reinterpret_cast<const std::byte*>(header) +
                                             sizeof(RingHeader));
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
    RingWriter(void* memory, std::uint32_t slot_count) : header_(static_cast<RingHeader*>(memory)) {
        header_->magic = kRingMagic;
        header_->version = kRingVersion;
        header_->header_size = sizeof(RingHeader);
        header_->slot_size = sizeof(RingSlot);
        header_->slot_count = slot_count;
        header_->flags.store(0, std::memory_order_relaxed);
        header_->wake.store(0, std::memory_order_relaxed);
        header_->published.store(0, std::memory_order_release);
    }

    // Writes the next sample and bumps the futex word; the caller then wakes
    // the waiters (futex_wake_all(wake_word())).
    void publish(const RingSample& sample) {
        const std::uint64_t n = header_->published.load(std::memory_order_relaxed) + 1;
        RingSlot& slot = ring_detail::slots(header_)[(n - 1) % header_->slot_count];
        slot.seq.store(2 * n - 1, std::memory_order_relaxed);
        std::atomic_thread_fence(std::memory_order_release);
        const auto words = ring_detail::to_words(sample);
        for (std::size_t i = 0; i < kRingSampleWords; ++i) {
            slot.words[i].store(words[i], std::memory_order_relaxed);
        }
        slot.seq.store(2 * n, std::memory_order_release);
        header_->published.store(n, std::memory_order_release);
        header_->wake.fetch_add(1, std::memory_order_release);
    }

    // No more samples will come (gportd is stopping); readers see closed().
    void close() {
        header_->flags.fetch_or(kRingFlagClosed, std::memory_order_release);
        header_->wake.fetch_add(1, std::memory_order_release);
    }

    std::atomic<std::uint32_t>& wake_word() { return header_->wake; }
    std::uint64_t published() const { return header_->published.load(std::memory_order_acquire); }

  private:
    RingHeader* header_;
};

// A reader over a mapping of the whole block (read-only is enough).
class RingReader {
  public:
    // Checks the header against the mapping's size; the error names what is
    // wrong. A reader is only made from a block that passed.
    static std::optional<std::string> check(const void* memory, std::size_t size) {
        if (size < sizeof(RingHeader)) {
            return "the block is smaller than a ring header";
        }
        const auto* h = static_cast<const RingHeader*>(memory);
        if (h->magic != kRingMagic) {
            return "not an attitude ring (bad magic)";
        }
        if (h->version != kRingVersion) {
            return "attitude ring version " + std::to_string(h->version) + " is not supported (" +
                   std::to_string(kRingVersion) + " is)";
        }
        if (h->header_size != sizeof(RingHeader) || h->slot_size != sizeof(RingSlot)) {
            return "attitude ring header or slot size does not match version 1";
        }
        if (h->slot_count == 0 || (h->slot_count & (h->slot_count - 1)) != 0) {
            return "attitude ring slot count is not a power of two";
        }
        if (size < ring_bytes(h->slot_count)) {
            return "the block is smaller than its ring";
        }
        return std::nullopt;
    }

    explicit RingReader(const void* memory) : header_(static_cast<const RingHeader*>(memory)) {}

    std::uint64_t published() const { return header_->published.load(std::memory_order_acquire); }
    std::uint32_t slot_count() const { return header_->slot_count; }
    bool closed() const {
        return (header_->flags.load(std::memory_order_acquire) & kRingFlagClosed) != 0;
    }
    // The futex word to wait on: read it, check for new samples, then wait
    // while it still holds the value read.
    const std::atomic<std::uint32_t>& wake_word() const { return header_->wake; }

    // Sample n, if it is still in the ring and complete.
    std::optional<RingSample> read(std::uint64_t n) const {
        if (n == 0) {
            return std::nullopt;
        }
        const RingSlot& slot = ring_detail::slots(header_)[(n - 1) % header_->slot_count];
        const std::uint64_t before = slot.seq.load(std::memory_order_acquire);
        if (before != 2 * n) {
            return std::nullopt;  // being written, overwritten, or not written yet
        }
        std::array<std::uint64_t, kRingSampleWords> words{};
        for (std::size_t i = 0; i < kRingSampleWords; ++i) {
            words[i] = slot.words[i].load(std::memory_order_relaxed);
        }
        std::atomic_thread_fence(std::memory_order_acquire);
        if (slot.seq.load(std::memory_order_relaxed) != before) {
            return std::nullopt;  // overwritten while read
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
            } else if (lapped || newest - cursor > header_->slot_count) {
                want = std::max(cursor + 1, newest - header_->slot_count / 2);
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
};

}  // namespace gport::base
