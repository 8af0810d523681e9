// The library's side of the shared-memory attitude channel (docs/api.md,
// "Shared-memory attitude channel"; docs/client-cpp.md):
//
// - ChannelMapping: one connection's two blocks (the ring and its wake
//   block), checked before they are mapped (size, seals) and after (header),
//   mapped read-only, and the relay state every reader of the connection in
//   this process shares. gportd wakes ONE waiter per sample on the
//   connection's word; the first thread of this process to see a new value
//   of the word wakes the others (relay()), so many threads cost gportd
//   nothing more. A Connection or AsyncClient caches its mapping: later
//   attitude_channel replies carry "descriptors":0 and share it.
// - AttitudeChannel::Impl: a reader with its own cursor over a mapping.
// - RingWaker: a thread that turns the word's changes into a pollable
//   eventfd (AttitudeFeed's: for Client, AsyncClient and gportctl).
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <thread>

#include "gport/base/attitude_ring.hpp"
#include "gport/base/futex.hpp"
#include "gport/client/attitude_channel.hpp"
#include "gport/client/types.hpp"
#include "wake_relay.hpp"

namespace gport::client {

// What an attitude_channel result says, checked: version 2, a power-of-two
// slot count up to base::kRingMaxSlots, size == ring_bytes(slots), and 0 or
// 2 descriptors. Throws Error (kBadReply) naming what is wrong.
struct ChannelReply {
    std::uint32_t slots = 0;
    std::size_t size = 0;
    std::size_t descriptors = 0;
    static ChannelReply parse(const nlohmann::json& result);
};

class ChannelMapping {
  public:
    // Checks both descriptors (the seals first: F_SEAL_SHRINK and a write
    // seal; then the size: the ring's as the reply says, the wake block's
    // 64), maps
    // them read-only and checks their headers. Throws Error (kBadReply)
    // naming the block and the problem; the descriptors stay the caller's.
    static std::shared_ptr<ChannelMapping> map(int ring_fd, int wake_fd, const ChannelReply& reply);
    ~ChannelMapping();
    ChannelMapping(const ChannelMapping&) = delete;
    ChannelMapping& operator=(const ChannelMapping&) = delete;

    const base::RingReader& reader() const { return reader_; }
    const std::atomic<std::uint32_t>& word() const { return *word_; }
    // The word's value now (read it before looking for samples).
    std::uint32_t load() const { return word_->load(std::memory_order_acquire); }
    // Passes a wake on: when `seen` (a value of the word just loaded) is
    // newer than every value relayed yet, wakes every other waiter of this
    // process (WakeRelay: never backwards).
    void relay(std::uint32_t seen);
    // Sleeps while the word holds `seen`, at most `timeout`.
    base::FutexWait wait(std::uint32_t seen, std::chrono::nanoseconds timeout) const {
        return base::futex_wait(*word_, seen, timeout);
    }

  private:
    ChannelMapping(const void* ring, std::size_t ring_size, const void* wake);

    const void* ring_;
    std::size_t ring_size_;
    const void* wake_;
    base::RingReader reader_;
    const std::atomic<std::uint32_t>* word_;
    WakeRelay relayed_;
};

// Claims the channel an attitude_channel reply announces: with
// "descriptors":2 the first two of `fds` (the ring, then the wake block),
// mapped and checked, and closed here whatever happens; with 0 the cached
// mapping of this connection. Replaces `cache` with a new mapping. Throws
// Error: gportd's own error, or kBadReply naming what is wrong.
AttitudeChannel claim_channel(const nlohmann::json& reply, std::deque<int>& fds,
                              std::shared_ptr<ChannelMapping>& cache);

struct AttitudeChannel::Impl {
    explicit Impl(std::shared_ptr<ChannelMapping> m) : mapping(std::move(m)) {}

    // The next sample without waiting (see base::RingReader::next).
    std::optional<AttitudeSample> take();
    std::optional<AttitudeSample> next(std::chrono::milliseconds timeout);
    // From now on, take() gives only samples published after this call,
    // each of them (from sample 1 when none was published yet).
    void skip_to_newest() {
        cursor = reader().published();
        from_first = cursor == 0;
    }
    const base::RingReader& reader() const { return mapping->reader(); }

    std::shared_ptr<ChannelMapping> mapping;
    std::uint64_t cursor = 0;
    bool from_first = false;  // cursor 0 means "the newest" to RingReader
    std::atomic<std::uint64_t> missed{0};
};

// One thread per channel that sleeps on the connection's futex word and
// makes an eventfd readable whenever the word changed (a sample, or the
// close), relaying the wake like any reader. The consumer polls fd(), calls
// reset() and then takes every sample there is. The eventfd starts
// readable, so the consumer looks once after making it.
class RingWaker {
  public:
    explicit RingWaker(std::shared_ptr<ChannelMapping> mapping);
    RingWaker(const RingWaker&) = delete;
    RingWaker& operator=(const RingWaker&) = delete;
    ~RingWaker();

    int fd() const noexcept { return eventfd_; }
    void reset() noexcept;

  private:
    void run();

    std::shared_ptr<ChannelMapping> mapping_;
    std::uint32_t seen_;
    int eventfd_ = -1;
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

AttitudeSample to_attitude(const base::RingSample& sample, std::uint64_t dropped);

}  // namespace gport::client
