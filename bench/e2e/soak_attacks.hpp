// The soak's attacks on the daemon, run alongside the random workers:
//   (a) bursts: 96 `speed` requests and one `stop` in a single write — the
//       stop must never be refused for queue space and must reach the wire;
//   (b) settings floods: a wave of clients pipelining get_settings when the
//       gimbal falls silent — at most 4 may be outstanding per client and 64
//       in all, the rest refused with -32005;
//   (c) batch clients that send 32-request status batches and never read;
//   (d) idle connections that send nothing, hoarded;
//   (e) SIGHUP to gportd every few seconds.
// Each keeps its own connections; the driver polls them with its own.
// check_burst_trace() then looks for each burst's stop in the gimbal's trace.
#pragma once

#include <poll.h>
#include <sys/types.h>

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "posix.hpp"

namespace gport::bench {

struct AttackOptions {
    std::string socket;
    pid_t pid = 0;
    int burst_every_ms = 2500;
    int flood_clients = 20;
    int flood_depth = 8;  // get_settings pipelined per flood client
    int batch_clients = 4;
    int hoarders = 48;
    // The daemon's idle timeout for connections without subscriptions, as
    // the soak assumes it: a hoarder still open after twice this is a
    // violation (so runs shorter than that cannot see one).
    int idle_timeout_s = 15;
    int sighup_every_ms = 3000;
};

// One burst as the burst client saw it; `marker` is the yaw, in 0.01 deg,
// that its speed frames carry (roll 3.21, pitch -3.21) in the gimbal's trace.
struct Burst {
    int marker = 0;
    std::int64_t sent_ns = 0;
    bool answered = false;
    int stop_code = 0;  // 0: the stop succeeded
    std::string stop_message;
};

// A connection whose replies are read and counted by error code.
struct Conn {
    Fd fd;
    std::string pending;
    std::int64_t opened_ns = 0;
    int expected = 0;          // replies still to come
    std::map<int, int> codes;  // 0 for results
};

// The bursts whose stop succeeded but whose zero speed never followed their
// speed frames in gport-sim's trace (a vanished device excuses one).
struct TraceVerdict {
    std::uint64_t checked = 0;
    std::uint64_t excused = 0;  // the device vanished meanwhile
    std::uint64_t unseen = 0;   // none of its speeds reached the gimbal: the stop replaced them all
    std::vector<std::string> problems;
};
TraceVerdict check_burst_trace(const std::string& trace_path, const std::vector<Burst>& bursts);

class Attacks {
  public:
    explicit Attacks(AttackOptions o) : o_(std::move(o)) {}

    void act(std::int64_t t_ns);
    // The watcher saw the link change: a `stale` is the gimbal falling silent.
    void on_link(const std::string& state, std::int64_t t_ns);
    // Appends the descriptors to poll for reading; on_polled() takes them back
    // in the same order.
    void append_pollfds(std::vector<pollfd>& fds);
    void on_polled(const pollfd* fds, std::size_t count, std::int64_t t_ns);
    void finish();

    const std::vector<Burst>& bursts() const { return bursts_; }
    // Problems against the required behaviour; empty when all is well.
    std::vector<std::string> problems() const;
    nlohmann::json figures() const;

  private:
    void start_burst(std::int64_t t_ns);
    void on_burst_line(const std::string& line);
    void start_flood(std::int64_t t_ns);
    void end_flood();
    void feed_batches(std::int64_t t_ns);
    void keep_hoarding(std::int64_t t_ns);

    AttackOptions o_;
    // (a)
    Conn burst_;
    std::vector<Burst> bursts_;
    std::int64_t next_burst_ns_ = 0;
    // (b)
    std::vector<Conn> flood_;
    std::int64_t flood_started_ns_ = 0;
    std::uint64_t floods_ = 0;
    int max_per_client_ = 0;  // requests that reached the gimbal, one client, one wave
    int max_per_wave_ = 0;
    std::map<int, std::uint64_t> flood_codes_;
    // (c)
    std::vector<Conn> batchers_;
    std::vector<std::string> unsent_;
    std::int64_t next_batch_ns_ = 0;
    std::uint64_t batches_written_ = 0;
    std::uint64_t batchers_closed_ = 0;
    // (d)
    std::vector<Conn> hoard_;
    std::uint64_t hoarders_closed_ = 0;
    std::int64_t max_hoard_age_ns_ = 0;  // the longest a silent connection stayed open
    std::int64_t now_ns_ = 0;
    std::vector<Conn*> polled_;  // in append_pollfds() order
    // (e)
    std::int64_t next_hup_ns_ = 0;
    std::uint64_t hups_ = 0;
};

}  // namespace gport::bench
