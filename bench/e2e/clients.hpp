// The benchmark's clients of gportd, all served by one epoll loop on the
// main thread: subscribers that stamp every attitude line they read, and
// flooders that send `status` requests as fast as the replies come back.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "posix.hpp"

namespace gport::bench {

// One attitude line as a subscriber read it.
struct Receipt {
    std::uint32_t counter = 0;  // the frame's counter (see fake_gimbal.hpp)
    std::int64_t t_ns = 0;      // when the read() that brought it returned
};

struct Subscriber {
    Fd fd;
    std::string pending;                 // an incomplete line
    std::vector<Receipt> receipts;       // attitude lines, in arrival order
    std::uint64_t reported_dropped = 0;  // the largest "dropped" the daemon reported
    std::uint64_t out_of_order = 0;      // counters not above the previous one
    bool subscribed = false;             // the subscribe reply arrived
    bool closed = false;                 // the daemon closed the connection
};

struct Flooder {
    Fd fd;
    std::string pending;
    std::uint64_t next_id = 1;
    std::uint64_t replies = 0;
    bool closed = false;
};

class ClientHub {
  public:
    ClientHub();

    // Connects `count` subscribers and subscribes each to attitude; waits
    // for every reply (throws std::runtime_error after timeout_ms).
    void add_subscribers(const std::string& socket, int count, int timeout_ms);
    // Connects `count` flooders; they start sending on start_flood().
    void add_flooders(const std::string& socket, int count);

    void start_flood();
    void stop_flood() { flooding_ = false; }

    // Serves every client for `duration_ms`.
    void run_for(int duration_ms);

    const std::vector<Subscriber>& subscribers() const { return subscribers_; }
    // Every subscriber has the line of the frame with counter `last` (or a
    // later one), or its connection closed.
    bool caught_up(std::uint32_t last) const;
    // Adds readers measured elsewhere (the shared-memory channel's) to the
    // subscribers the report counts; they are not served by this hub.
    void adopt(std::vector<Subscriber> measured);
    const std::vector<Flooder>& flooders() const { return flooders_; }
    std::uint64_t flood_replies() const;

  private:
    void watch(int fd, std::uint64_t key);
    void poll_once(int timeout_ms);
    void on_subscriber(Subscriber& s);
    void on_flooder(Flooder& f);
    void send_request(Flooder& f);

    Fd epoll_;
    std::vector<Subscriber> subscribers_;
    std::vector<Flooder> flooders_;
    bool flooding_ = false;
};

}  // namespace gport::bench
