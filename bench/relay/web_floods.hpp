// The floods on gport-web, all on one thread of their own (one io_context):
// keep-alive HTTP connections each sending its next request as soon as the
// answer came, and control WebSockets jogging at a fixed rate. Peers are
// spread over 127.0.0.2, .3, ... so that gport-web's 16 connections per
// address admit them.
#pragma once

#include <atomic>
#include <boost/asio/io_context.hpp>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "web_client.hpp"

namespace gport::bench::relay {

struct WebFloodCounters {
    std::atomic<std::uint64_t> answers{0};     // HTTP answers (any status)
    std::atomic<std::uint64_t> refused{0};     // of them, not 2xx
    std::atomic<std::uint64_t> errors{0};      // transport errors (then a reconnect)
    std::atomic<std::uint64_t> jogs{0};        // WebSocket jogs written
    std::atomic<std::uint64_t> ws_closed{0};   // WebSockets gport-web closed
    std::atomic<std::uint64_t> body_bytes{0};  // answer bodies

    // Answers by status other than 200, and the first transport error, as text.
    std::string summary() const;
    void count_status(unsigned status);
    void count_error(const std::string& what);

  private:
    mutable std::mutex mutex_;
    std::map<unsigned, std::uint64_t> statuses_;
    std::string first_error_;
};

// What a scenario floods with.
struct WebFloodSpec {
    int http_connections = 0;
    std::string token;                 // the HTTP connections' token
    std::vector<std::string> targets;  // each connection cycles through them
    int jog_sockets = 0;               // control WebSockets
    double jog_hz = 25;                // messages per second each
    double jog_yaw_dps = 0.2;          // never zero: the floods make no zero-speed frame
};

// The flood of a scenario name ("none", "view-status", "view-mixed", "csv", "jog").
WebFloodSpec web_flood_spec(const std::string& flood, const WebTarget& web);

class WebFlood {
  public:
    // Opens every connection (blocking), then floods on its own thread.
    WebFlood(const WebTarget& web, const WebFloodSpec& spec);
    ~WebFlood();
    WebFlood(const WebFlood&) = delete;
    WebFlood& operator=(const WebFlood&) = delete;

    // Closes every connection and joins the thread.
    void stop();
    const WebFloodCounters& counters() const { return counters_; }

  private:
    asio::io_context io_;
    WebFloodCounters counters_;
    std::shared_ptr<std::atomic<bool>> stopping_ = std::make_shared<std::atomic<bool>>(false);
    std::vector<std::function<void()>> closers_;
    std::thread thread_;
};

}  // namespace gport::bench::relay
