// Readers of gportd's shared-memory attitude channel for the benchmarks
// (docs/performance.md, "Shared-memory channel"). By default each reader has
// its own connection and mappings and runs on its own thread blocking in
// futex_wait, as separate processes would; with `threads` > 0 the readers
// share that many threads (round robin) and each thread's readers share one
// connection (as the readers of one process share their Client's channel),
// so the daemon wakes only that many connections per sample. Each reader
// keeps its own cursor.
// Every sample is stamped when it is read, on the clock the socket
// subscribers use, so both give latencies from the frame's last byte.
#pragma once

#include <atomic>
#include <cstddef>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "clients.hpp"
#include "posix.hpp"

namespace gport::bench {

class ShmReaders {
  public:
    // Connects `count` clients and opens the channel on each; throws
    // std::runtime_error naming what failed. `expected_samples` sizes the
    // receipt buffers so no allocation happens while measuring.
    ShmReaders(const std::string& socket, int count, std::size_t expected_samples, int threads = 0);
    ~ShmReaders();
    ShmReaders(const ShmReaders&) = delete;
    ShmReaders& operator=(const ShmReaders&) = delete;

    // Starts the reader threads; each first takes the newest sample, if any.
    void start();
    // Stops and joins them (a waiting reader notices within 100 ms).
    void stop();
    // Every reader has taken the frame with counter `last` (or a later one).
    bool caught_up(std::uint32_t last) const;

    // What each reader read, as a Subscriber (receipts, out_of_order, and
    // the samples it missed in reported_dropped), for the report's
    // delivery and latency figures. Valid after stop().
    std::vector<Subscriber> take_results();
    // Futex waits that ended in a wake, over all readers.
    std::uint64_t wakes() const;

  private:
    struct Reader;
    void run(const std::vector<Reader*>& readers);
    static bool take(Reader& reader);

    std::vector<std::unique_ptr<Reader>> readers_;
    int thread_count_;
    std::vector<std::thread> threads_;
    std::atomic<bool> stop_{false};
};

}  // namespace gport::bench
