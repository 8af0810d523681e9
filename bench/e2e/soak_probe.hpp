// The soak's well-behaved subscriber: on its own thread (so the driver's
// busy loop cannot delay it), it subscribes to attitude and link and measures
// the gaps between attitude notifications. A gap during which a link
// notification arrived is the gimbal's doing (a silence, a vanished device)
// and is excused; any other long gap means the daemon starved this client.
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

namespace gport::bench {

struct ProbeFigures {
    std::uint64_t attitude_lines = 0;
    std::uint64_t excused_gaps = 0;  // a link change explains them
    double max_gap_ms = 0;           // the longest gap not excused
    std::uint64_t gaps_over_limit = 0;
    bool connected = false;
    bool closed_by_daemon = false;
};

class SubscriberProbe {
  public:
    SubscriberProbe(std::string socket, double limit_ms)
        : socket_(std::move(socket)), limit_ms_(limit_ms) {}
    ~SubscriberProbe() { stop(); }
    SubscriberProbe(const SubscriberProbe&) = delete;
    SubscriberProbe& operator=(const SubscriberProbe&) = delete;

    void start();
    void stop();
    ProbeFigures figures() const;

  private:
    void run();
    void on_line(const std::string& line);

    std::string socket_;
    double limit_ms_;
    std::thread thread_;
    std::atomic<bool> stop_{false};
    mutable std::mutex mutex_;
    ProbeFigures figures_;
    std::int64_t last_attitude_ns_ = 0;
    bool link_changed_ = false;  // since the last attitude
};

}  // namespace gport::bench
