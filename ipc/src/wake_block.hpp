// One connection's wake block of the attitude channel (base/wake_block.hpp):
// a 64-byte memfd ("gportd-wake"), mapped read-write here and then sealed
// like the ring (F_SEAL_SHRINK | F_SEAL_GROW | F_SEAL_FUTURE_WRITE |
// F_SEAL_SEAL), so the connection can only map it read-only.
//
// gportd keeps the descriptor only until it has been sent
// (forget_descriptor()); the mapping stays until the connection closed and
// the waker thread let go of it (the last shared owner unmaps it).
#pragma once

#include <memory>
#include <string>
#include <variant>

#include "gport/base/wake_block.hpp"

namespace gport::ipc::detail {

class WakeBlock {
  public:
    // A new block, or why it could not be made (the step and strerror).
    static std::variant<std::unique_ptr<WakeBlock>, std::string> make();
    ~WakeBlock();
    WakeBlock(const WakeBlock&) = delete;
    WakeBlock& operator=(const WakeBlock&) = delete;

    // The memfd, -1 once forgotten.
    int fd() const { return fd_; }
    // Closes gportd's copy of the descriptor (the peer has its own).
    void forget_descriptor();
    // Bumps the word and wakes one waiter: what a sample or the close costs
    // per connection. Returns how many were woken (0 or 1), or -1. The loop
    // or the waker thread calls it (channel_waker.hpp); it touches nothing but the shared word, so
    // the loop may meanwhile forget the descriptor.
    long bump_and_wake() const;
    const std::atomic<std::uint32_t>& word() const { return block_->wake; }

    // Slow wakes counted against the connection while the loop woke it
    // (ChannelWaker::kStrikes hand it to the thread). The loop's only: the
    // thread never reads them.
    int strikes() const { return strikes_; }
    int strike() const { return ++strikes_; }

  private:
    WakeBlock(int fd, void* memory);

    int fd_;
    void* memory_;
    base::WakeBlock* block_;
    mutable int strikes_ = 0;
};

}  // namespace gport::ipc::detail
