// The attitude channel's wakes (docs/architecture.md, "Threads"): the only
// place where gportd bumps the readers' wake words and calls FUTEX_WAKE.
//
// The first kInline reader connections are woken on the loop itself, at
// once: one bump and one FUTEX_WAKE(1) each, about 2-4 us, with no hand-off
// between threads in the sample's way (a typical vehicle has a handful of
// reader processes, and a process's readers share one connection). Every
// other connection is woken by a thread of its own, so that nothing a
// reader does adds more than that bounded time to the event loop: many
// threads parked on its word, or waiters on other words that share its
// futex hash bucket, make each FUTEX_WAKE walk them all under the bucket's
// lock; a connection whose wake on the loop took longer than kSlowWake
// kStrikes times is handed to the thread for good.
//
//   ChannelWaker waker;
//   waker.start();             // the thread (on the first attitude_channel), or why not
//   waker.set_blocks(blocks);  // loop: the connections to wake from the next sample on
//   waker.signal();            // loop, per sample: at most kInline wakes, never blocks
//   waker.close();             // loop, at shutdown: a last wake for every block, then joins
//
// The loop's share of the thread's work is one counter increment, one
// atomic exchange and, only when the thread has taken the previous signal
// (and has blocks to wake), one write to an eventfd that nobody else can
// wait on. Signals that come while a round runs are answered by one more
// round: several samples may share one bump of a word (a reader looks at
// the ring, not at the count). The loop never takes a lock the thread holds
// and never waits for it, except in close().
//
// The thread's blocks are handed over as an immutable snapshot through a
// one-slot mailbox (an atomic pointer): the loop replaces it whenever a
// connection's descriptors were sent, a reader connection closed or a
// connection was handed over; the thread takes the newest at the start of
// each round. Blocks are shared: the thread keeps its snapshot's blocks
// mapped until it takes the next, so a block is never unmapped under a
// wake, and a round already under way when a connection closed may bump
// its word one last time; after that, never again.
#pragma once

#include <pthread.h>

#include <atomic>
#include <chrono>
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
    using Clock = std::chrono::steady_clock;

    // Connections woken on the loop, the oldest first.
    static constexpr std::size_t kInline = 8;
    // A wake on the loop longer than this is a strike against its connection
    // (an honest one takes a few microseconds)...
    static constexpr Clock::duration kSlowWake = std::chrono::microseconds(50);
    // ... and this many hand it to the thread.
    static constexpr int kStrikes = 3;

    // slow_wake: kSlowWake, but in the tests of the hand-over.
    explicit ChannelWaker(Clock::duration slow_wake = kSlowWake) : slow_wake_(slow_wake) {}
    ~ChannelWaker();
    ChannelWaker(const ChannelWaker&) = delete;
    ChannelWaker& operator=(const ChannelWaker&) = delete;

    // Starts the thread the first time (later calls do nothing); the error
    // names the step that failed (eventfd, pthread_create) and why.
    std::optional<std::string> start();
    bool running() const { return started_ && !closed_; }

    // The blocks every later sample wakes (the loop's side).
    void set_blocks(Blocks blocks);
    // A new sample: the first blocks are woken now, the thread makes a round
    // over the others soon. Does nothing before start() or after close().
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
    // Connections woken on the loop now, and handed to the thread for
    // their slow wakes so far (the loop's side).
    std::size_t inline_count() const { return inline_.size(); }
    std::size_t handed_over() const { return handed_over_; }

  private:
    static void* main(void* self);
    void run();
    void take_blocks();
    void round();
    void notify();
    // The loop's side: the first kInline blocks with fewer than kStrikes go
    // to inline_, the rest to the thread's mailbox.
    void split();
    void wake_inline();

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

    // The loop's own: every block, and those it wakes itself.
    Clock::duration slow_wake_;
    Blocks all_;
    Blocks inline_;
    bool threaded_ = false;  // the thread has blocks to wake
    std::size_t handed_over_ = 0;
};

}  // namespace gport::ipc::detail
