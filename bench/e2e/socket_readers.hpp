// Socket subscribers for the benchmark, each on its own thread blocking in
// read(), as separate client processes would be: the fair counterpart of
// ShmReaders (one thread per reader, so each frame costs the daemon one
// wake-up per reader either way). The default subscribers of bench_e2e
// share one epoll loop instead, which the daemon wakes once per frame.
#pragma once

#include <atomic>
#include <cstddef>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "clients.hpp"

namespace gport::bench {

class SocketReaders {
  public:
    // Connects `count` subscribers to attitude and waits for every
    // subscribe reply; throws std::runtime_error naming what failed.
    SocketReaders(const std::string& socket, int count, std::size_t expected_lines);
    ~SocketReaders();
    SocketReaders(const SocketReaders&) = delete;
    SocketReaders& operator=(const SocketReaders&) = delete;

    // Stops and joins the threads (a blocked read() times out within 100 ms).
    void stop();
    // Every reader has the line of the frame with counter `last` (or a later
    // one), or its connection closed.
    bool caught_up(std::uint32_t last) const;
    // What each read, for the report. Valid after stop().
    std::vector<Subscriber> take_results();

  private:
    struct Reader;
    void run(Reader& reader);

    std::vector<std::unique_ptr<Reader>> readers_;
    std::vector<std::thread> threads_;
    std::atomic<bool> stop_{false};
};

}  // namespace gport::bench
