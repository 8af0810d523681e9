// The attitude channel's waker thread (docs/architecture.md, "Threads"):
// the only place where gportd bumps the readers' wake words and calls
// FUTEX_WAKE, so that nothing a reader does — many threads parked on its
// word, waiters on other words that share its futex hash bucket (which
// make each FUTEX_WAKE walk them all under the bucket's lock), many
// connections — adds time to the event loop.
//
//   ChannelWaker waker;
//   waker.start();             // the thread (on the first attitude_channel), or why not
//   waker.set_blocks(blocks);  // loop: the connections to wake from the next round on
//   waker.signal();            // loop, per sample: O(1), never blocks
//   waker.close();             // loop, at shutdown: a last round for every block, then joins
//
// The loop's side of a sample is one counter increment, one atomic
// exchange and, only when the thread has taken the previous signal, one
// write to an eventfd that nobody else can wait on. Signals that come while
// a round runs are answered by one more round: several samples may share
// one bump of a word (a reader looks at the ring, not at the count). The
// loop never takes a lock the thread holds and never waits for it, except
// in close().
//
// The set of blocks is handed over as an immutable snapshot through a
// one-slot mailbox (an atomic pointer): the loop replaces it whenever a
// connection's descriptors were sent or a reader connection closed; the
// thread takes the newest at the start of each round. Blocks are shared:
// the thread keeps its snapshot's blocks mapped until it takes the next, so
// a block is never unmapped under a wake, and a round already under way
// when a connection closed may bump its word one last time; after that,
// never again.
#pragma once

#include <pthread.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "wake_block.hpp"

namespace gport::ipc::detail {

class ChannelWaker {
  public:
    using Blocks = std::vector<std::shared_ptr<const WakeBlock>>;

    ChannelWaker() = default;
    ~ChannelWaker();
    ChannelWaker(const ChannelWaker&) = delete;
    ChannelWaker& operator=(const ChannelWaker&) = delete;

    // Starts the thread the first time (later calls do nothing); the error
    // names the step that failed (eventfd, pthread_create) and why.
    std::optional<std::string> start();
    bool running() const { return started_ && !closed_; }

    // The blocks every later round wakes (the loop's side; any thread that
    // is the only caller).
    void set_blocks(Blocks blocks);
    // A new sample: the thread makes a round soon. Does nothing before
    // start() or after close().
    void signal();
    // A last round over the newest blocks (the channel's closed flag must be
    // set before), then the thread ends and is joined. Idempotent.
    void close();

    // Every signal so far has been answered by a finished round.
    bool idle() const {
        return handled_.load(std::memory_order_acquire) ==
               requested_.load(std::memory_order_acquire);
    }
    std::uint64_t rounds() const { return rounds_.load(std::memory_order_relaxed); }

  private:
    static void* main(void* self);
    void run();
    void take_blocks();
    void round();
    void notify();

    int event_ = -1;  // eventfd: the loop writes, the thread reads
    pthread_t thread_{};
    bool started_ = false;
    bool closed_ = false;
    std::atomic<bool> signalled_{false};  // a signal the thread has not taken yet
    std::atomic<bool> stopping_{false};
    std::atomic<std::uint64_t> requested_{0};  // signals given (loop)
    std::atomic<std::uint64_t> handled_{0};    // signals answered by finished rounds (thread)
    std::atomic<std::uint64_t> rounds_{0};
    std::atomic<Blocks*> mailbox_{nullptr};  // the newest snapshot, until the thread takes it
    Blocks blocks_;                          // the thread's own snapshot
};

}  // namespace gport::ipc::detail
