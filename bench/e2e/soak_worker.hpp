// One of the soak driver's clients: it connects, learns its daemon client id,
// and then does random things (subscribe, move, stop, settings, stall,
// disconnect) at random intervals, counting the replies it gets.
#pragma once

#include <cstdint>
#include <map>
#include <random>
#include <string>

#include "posix.hpp"

namespace gport::bench {

struct WorkerTally {
    std::uint64_t requests = 0;
    std::uint64_t replies = 0;
    std::uint64_t attitude_lines = 0;
    std::uint64_t connects = 0;
    std::uint64_t disconnects = 0;
    std::uint64_t refused = 0;            // closed by the daemon (e.g. a stalled reader)
    std::map<int, std::uint64_t> errors;  // JSON-RPC error code -> count
};

class Worker {
  public:
    Worker(std::string socket, std::uint32_t seed) : socket_(std::move(socket)), rng_(seed) {}

    // Does what is due at t_ns. Returns the daemon id of a client that just
    // disconnected (0 if none), so the deadman check hears of it.
    std::uint64_t act(std::int64_t t_ns, WorkerTally& tally);
    // Reads what arrived; false when the daemon closed the connection.
    bool on_readable(WorkerTally& tally);
    // Closes the connection (end of the run); returns the daemon id, or 0.
    std::uint64_t disconnect(WorkerTally& tally);

    int fd() const { return fd_.get(); }
    bool connected() const { return fd_.valid(); }
    // A stalled worker does not read, to exercise the daemon's back-pressure.
    bool stalled(std::int64_t t_ns) const { return t_ns < stalled_until_; }
    std::int64_t next_action_ns() const { return next_ns_; }
    std::uint64_t daemon_id() const { return id_; }

  private:
    void connect(std::int64_t t_ns, WorkerTally& tally);
    void random_request(std::int64_t t_ns, WorkerTally& tally);
    void send(const std::string& method, const std::string& params, WorkerTally& tally);
    void on_line(const std::string& line, WorkerTally& tally);
    std::int64_t after_ms(std::int64_t t_ns, int low, int high);
    double uniform(double low, double high);

    std::string socket_;
    std::mt19937 rng_;
    Fd fd_;
    std::string pending_;
    std::uint64_t id_ = 0;  // the daemon's id for this connection (from status)
    std::uint64_t next_request_ = 1;
    std::int64_t next_ns_ = 0;
    std::int64_t stalled_until_ = 0;
    bool broken_ = false;
    bool holds_control_ = false;  // it sent acquire and has not released yet  // a request could
                                  // not be sent: the connection is given up
};

}  // namespace gport::bench
