// The futex-waiter attack of issue 22 (problem 2), for bench_e2e
// --park-threads N [--park-gone] and the soak: a read-only peer in a
// process of its own (this program re-executed with --park-child) opens the
// attitude channel and parks N threads in FUTEX_WAIT on the word gportd
// wakes — against a version 1 daemon the ring header's word (offset 24),
// against version 2 its connection's own wake block (offset 16) — each
// going straight back to sleep when woken, never passing a wake on. With
// `gone` the peer closes its socket once its threads are parked and keeps
// them parked; a holder connection of this process then keeps the channel
// open, so gportd still has a reader to wake (the "+ 1 real holder").
// With `keys` > 0 (review finding 5) the threads park instead on that many
// words of a shared memfd of the peer's own, none on the wake word: every
// futex hash bucket holds some, so each FUTEX_WAKE gportd makes on the
// peer's word walks a chain of waiters it never wakes (the timed search for
// keys colliding with that word concentrates them in its bucket; covering
// every bucket needs no timing).
#pragma once

#include <sys/types.h>

#include <memory>
#include <string>

#include "posix.hpp"

namespace gport::bench {

class ParkAttack {
  public:
    // Starts the peer and waits until its threads are parked; throws
    // std::runtime_error naming what failed.
    ParkAttack(const std::string& socket, int threads, bool gone, int keys = 0);
    ~ParkAttack();
    ParkAttack(const ParkAttack&) = delete;
    ParkAttack& operator=(const ParkAttack&) = delete;

    int threads() const { return threads_; }
    bool gone() const { return gone_; }
    int keys() const { return keys_; }
    // The channel's layout version the daemon announced (1 or 2).
    int version() const { return version_; }
    // Ends the peer (SIGKILL) and reaps it.
    void stop();

  private:
    int threads_;
    bool gone_;
    int keys_;
    int version_ = 0;
    std::unique_ptr<testing::Process> child_;
    Fd holder_;
};

// The peer's main (argv after --park-child: SOCKET THREADS GONE(0|1) FD KEYS):
// writes "parked <version>\n" to FD once its threads are parked.
int park_child_main(int argc, char** argv);

}  // namespace gport::bench
