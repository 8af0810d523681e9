// Which thread of this process passes a wake on (ChannelMapping::relay):
// gportd wakes one waiter per change of the connection's word; the first
// thread to see a value newer than every value relayed so far wakes the
// others. Only forward: a thread that loaded an older value and was
// preempted can neither move the state back nor cause another wake-all
// (values compared modulo 2^32, as the word wraps).
#pragma once

#include <atomic>
#include <cstdint>

namespace gport::client {

class WakeRelay {
  public:
    explicit WakeRelay(std::uint32_t now) noexcept : relayed_(now) {}

    // True for the one call that first brings a value newer than every one
    // before: its caller wakes the others.
    bool claim(std::uint32_t seen) noexcept {
        std::uint32_t last = relayed_.load(std::memory_order_acquire);
        while (newer(seen, last)) {
            if (relayed_.compare_exchange_weak(last, seen, std::memory_order_acq_rel)) {
                return true;
            }
        }
        return false;
    }

    static bool newer(std::uint32_t seen, std::uint32_t last) noexcept {
        return static_cast<std::int32_t>(seen - last) > 0;
    }

  private:
    std::atomic<std::uint32_t> relayed_;
};

}  // namespace gport::client
