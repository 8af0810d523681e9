// The pure JSON-RPC 2.0 layer: one request line in, reply lines out through a
// sink. No sockets here; the session feeds it lines and queues what it emits,
// so tests and the fuzzer drive it directly.
//
// Decisions (docs/api.md has the user-facing version):
// - "jsonrpc" is optional on input and must be "2.0" when present; every
//   reply carries "jsonrpc":"2.0".
// - A request without "id" is a notification: it runs, nothing is sent back.
//   "id" may be a number, a string (at most kMaxIdLength bytes) or null.
// - Batches (a JSON array of requests) are supported as JSON-RPC 2.0 says:
//   one array of replies, in request order, once every member has been
//   answered; nothing when all members are notifications; at most
//   kMaxBatch members.
// - Nesting deeper than kMaxDepth is refused with -32700 before nlohmann's
//   recursive parser ever sees it, so no input can exhaust the stack.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include "gport/base/token_bucket.hpp"
#include "gport/capture/capture_log.hpp"
#include "gport/contract/errors.hpp"
#include "gport/contract/limits.hpp"
#include "gport/daemon/api.hpp"
#include "gport/ipc/status_cache.hpp"

namespace gport::ipc {

// The wire contract (gport/contract/): the error codes (rpc_error::kBusy...)
// and the limits a request is checked against, under the names ipc uses.
namespace rpc_error = contract::rpc_error;
using contract::kMaxBatch;
using contract::kMaxDepth;
using contract::kMaxIdLength;
using contract::kMaxRateHz;
using contract::kMinRateHz;

// What one client has asked to receive.
struct Subscriptions {
    bool attitude = false;
    bool link = false;
    bool motion = false;
    bool capture = false;
    std::optional<double> max_rate_hz;  // attitude only; empty = every sample
};

// The requests a client may make: a base::TokenBucket of `per_second`
// tokens a second holding one second's worth, full until first used;
// per_second 0: no limit. A request takes one token, and what it cost the
// event loop beyond the loop's budget for one request is charged on top
// (charge(): one token per kCostPerToken, into a debt of at most one
// second's worth), so a costly request counts as several and a client that
// sends them waits longer.
class RequestRate {
  public:
    using Clock = std::chrono::steady_clock;
    static constexpr auto kCostPerToken = std::chrono::milliseconds(1);

    RequestRate() = default;
    explicit RequestRate(double per_second) : bucket_(per_second, per_second) {}

    double per_second() const { return bucket_.rate(); }
    bool limited() const { return per_second() > 0; }
    // Takes one token; false when none is left.
    bool take(Clock::time_point now) { return !limited() || bucket_.take(now); }
    // Spends tokens for `cost` of loop time beyond the first kCostPerToken.
    void charge(Clock::duration cost, Clock::time_point now);
    // At least one token is there at `now` (always, unlimited).
    bool has_token(Clock::time_point now) const { return !limited() || bucket_.level(now) >= 1; }
    // How long until `needed` tokens (at most one second's worth) are there.
    Clock::duration wait_for(double needed, Clock::time_point now) const {
        return limited() ? bucket_.wait_for(now, needed) : Clock::duration::zero();
    }

  private:
    base::TokenBucket bucket_{0, 0};
};

// Per-connection state the methods read and change.
struct ClientState {
    daemon::ClientInfo info;
    Subscriptions subscriptions;
    std::uint64_t dropped = 0;      // attitude notifications dropped for this client
    RequestRate rate;               // socket.max_requests_per_s; batch members count
    bool attitude_channel = false;  // it opened the shared-memory attitude channel
};

// Figures only the transport knows, added to the status result.
struct ServerStats {
    std::size_t clients = 0;
    std::uint64_t dropped_notifications = 0;   // over all clients since start
    std::size_t attitude_channel_clients = 0;  // connected clients that opened the channel
    // Channels not made or descriptors not sent (EMFILE, ETOOMANYREFS...) since start.
    std::uint64_t attitude_channel_failures = 0;
    // The longest one request held the event loop since start (a batch's
    // members each count alone), and its method.
    std::uint64_t worst_request_us = 0;
    std::string worst_method{};
    // The configuration file gportd loaded, or none (the built-in defaults).
    std::optional<std::string> config_file{};
};

// The shared-memory attitude channel as the attitude_channel method reports it.
struct ChannelInfo {
    std::uint32_t version = 0;
    std::uint32_t slots = 0;
    std::size_t size = 0;         // bytes of the block
    std::uint64_t published = 0;  // n of the newest sample, 0 if none
    // Descriptors that go with this reply: 2 (the ring and the connection's
    // wake block) on a connection's first request, 0 on later ones.
    std::size_t descriptors = 0;
};

// What the attitude_channel method needs from the transport, which owns the
// channel and sends its descriptor with the reply (docs/api.md,
// "Shared-memory attitude channel").
class ChannelHost {
  public:
    // Makes the channel on first use and counts `client` among its readers
    // (sets client.attitude_channel), with a wake block of its own; the
    // error says why it cannot be made. `deliver`: the reply will be sent,
    // so it may carry the descriptors (false for a notification). When it
    // does (ChannelInfo::descriptors 2), the transport attaches them to the
    // reply line of the request being handled, at the session: they never
    // pass through the JSON-RPC layer.
    virtual std::variant<ChannelInfo, std::string> open_attitude_channel(ClientState& client,
                                                                         bool deliver) = 0;

  protected:
    ChannelHost() = default;
    ~ChannelHost() = default;
    ChannelHost(const ChannelHost&) = default;
    ChannelHost& operator=(const ChannelHost&) = default;
};

// Receives complete reply lines, each ending in '\n'. May be called after
// handle_line returned (settings requests answer later).
using ReplySink = std::function<void(std::string line)>;

class Dispatcher {
  public:
    // `status_max_age`: how old the cached part of status may get (tests
    // pass other ages; the server uses the default).
    Dispatcher(daemon::Api& api, std::function<ServerStats()> stats,
               StatusCache::Clock::duration status_max_age = StatusCache::kMaxAge);
    Dispatcher(const Dispatcher&) = delete;  // its stats function refers to it
    Dispatcher& operator=(const Dispatcher&) = delete;

    // Handles one line (without its '\n'). Replies go to `sink`, zero or
    // more times: never for notifications, once for a request or a batch.
    void handle_line(std::string_view line, ClientState& client, const ReplySink& sink);

    // The transport that serves attitude_channel; without one the method
    // answers -32603.
    void set_channel_host(ChannelHost* host) { channel_host_ = host; }

    // The cached part of `status` (status_cache.hpp). Requests other than
    // status invalidate it themselves; the transport calls this when a
    // client connects or leaves and on link and motion events.
    void invalidate_status() { status_cache_.invalidate(); }
    const StatusCache& status_cache() const { return status_cache_; }

    // The captures of photo and record (capture_log.hpp).
    capture::CaptureLog& captures() { return captures_; }

    // The longest one request held the loop, and its method (status "loop").
    struct Worst {
        std::chrono::steady_clock::duration time{};
        std::string method;
    };
    const Worst& worst_request() const { return worst_; }

  private:
    daemon::Api& api_;
    std::function<ServerStats()> server_stats_;
    std::function<ServerStats()> stats_;  // server_stats_ and worst_
    Worst worst_;
    StatusCache status_cache_;
    ChannelHost* channel_host_ = nullptr;
    capture::CaptureLog captures_;
};

// Builds an error reply line ("id" null), for the transport's own errors:
// line too long, too many clients.
std::string error_line(int code, std::string_view message);

}  // namespace gport::ipc
