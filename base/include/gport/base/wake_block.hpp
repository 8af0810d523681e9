// The wake block of the shared-memory attitude channel: one 64-byte sealed
// memfd per connection that opened the channel, holding the futex word its
// readers sleep on (docs/api.md, "Shared-memory attitude channel"). gportd
// sends it only to that connection, so nobody else can wait on the word,
// steal its wakes or make waking it cost more than one small syscall: per
// sample gportd bumps `wake` and wakes ONE waiter (futex_wake(word, 1)); a
// process with several threads waiting on it passes the wake on itself.
//
// Layout, version 1 (native, little-endian on every supported machine):
//   0 u32 magic 0x57415047 ("GPAW" in little-endian memory)
//   4 u32 version (1)
//   8 u32 size (64)
//  12 u32 reserved (0)
//  16 u32 wake: the futex word, bumped per sample and when the channel closes
//  20..63 reserved (0)
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>

namespace gport::base {

inline constexpr std::uint32_t kWakeMagic = 0x57415047;  // "GPAW" in little-endian memory
inline constexpr std::uint32_t kWakeVersion = 1;

struct WakeBlock {
    std::uint32_t magic;
    std::uint32_t version;
    std::uint32_t size;  // sizeof(WakeBlock)
    std::uint32_t reserved0;
    std::atomic<std::uint32_t> wake;  // the futex word
    std::array<std::uint32_t, 11> reserved;
};

inline constexpr std::size_t kWakeBlockBytes = 64;
static_assert(sizeof(WakeBlock) == kWakeBlockBytes);
static_assert(offsetof(WakeBlock, wake) == 16);
static_assert(std::atomic<std::uint32_t>::is_always_lock_free);
static_assert(sizeof(std::atomic<std::uint32_t>) == sizeof(std::uint32_t));

// Formats zero-filled memory of kWakeBlockBytes (the writer: gportd).
inline WakeBlock* format_wake_block(void* memory) {
    auto* block = static_cast<WakeBlock*>(memory);
    block->magic = kWakeMagic;
    block->version = kWakeVersion;
    block->size = sizeof(WakeBlock);
    block->reserved0 = 0;
    block->wake.store(0, std::memory_order_release);
    return block;
}

// What is wrong with a mapped wake block of `size` bytes, or nothing.
inline std::optional<std::string> check_wake_block(const void* memory, std::size_t size) {
    if (size != kWakeBlockBytes) {
        return "the wake block is " + std::to_string(size) + " bytes, not " +
               std::to_string(kWakeBlockBytes);
    }
    struct {
        std::uint32_t magic, version, size;
    } h{};
    std::memcpy(&h, memory, sizeof(h));
    if (h.magic != kWakeMagic) {
        return "not an attitude channel wake block (bad magic)";
    }
    if (h.version != kWakeVersion) {
        return "wake block version " + std::to_string(h.version) + " is not supported (" +
               std::to_string(kWakeVersion) + " is)";
    }
    if (h.size != kWakeBlockBytes) {
        return "the wake block's header gives size " + std::to_string(h.size) + ", not " +
               std::to_string(kWakeBlockBytes);
    }
    return std::nullopt;
}

// The futex word of a checked, mapped block (read-only is enough to wait
// and to wake).
inline const std::atomic<std::uint32_t>& wake_word(const void* memory) {
    return static_cast<const WakeBlock*>(memory)->wake;
}

}  // namespace gport::base
