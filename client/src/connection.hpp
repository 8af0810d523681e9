// The transport under Client and gportctl: newline-delimited JSON-RPC over
// gportd's Unix socket, blocking, plain POSIX. Notifications that arrive
// while waiting for a reply go to a handler; reads give up when
// `interrupted()` turns true.
//
// Within the limits of gport/client/limits.hpp: a line from gportd over
// kLineLimit, nested deeper than kNestingLimit, not JSON or not an object
// ends the connection (failure() says why); call() waits for its reply at
// most the call timeout (kDefaultCallTimeout unless set).
//
// The socket is read with recvmsg: file descriptors gportd attaches to a
// reply (SCM_RIGHTS, only with a connection's first `attitude_channel`
// result) are kept as ChannelClaims allows (two, while the connection has
// no channel and an attitude_channel request sent with send() or call()
// awaits its reply); any others are closed at once.
//
// Internal to the library (not installed): the blocking Client's transport.
// Its symbols stay exported for the library's own tests (tests/client); its
// interface may change in any release.
#pragma once

#include <chrono>
#include <cstddef>
#include <deque>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

#include "channel_claims.hpp"
#include "gport/client/attitude_channel.hpp"
#include "gport/client/export.hpp"
#include "gport/client/limits.hpp"
#include "lines.hpp"

namespace gport::client {

class GPORT_CLIENT_API Connection {
  public:
    // Connects; throws Error (kTransport) naming the path and the reason.
    static Connection open(const std::string& path);

    Connection(Connection&& other) noexcept;
    Connection& operator=(Connection&& other) noexcept;
    Connection(const Connection&) = delete;
    Connection& operator=(const Connection&) = delete;
    ~Connection();

    // Sends a request (with a fresh id) and returns the id; empty on a broken
    // connection, or when gportd took no part of it within the call timeout
    // (the connection is closed then: failure() says so).
    std::optional<int> send(const std::string& method, const nlohmann::json& params);

    // kWoken: the descriptor given to watch() became readable (before any
    // message was complete).
    enum class ReadStatus { kMessage, kTimeout, kClosed, kInterrupted, kWoken };
    // The next message; waits at most `timeout` (forever when empty).
    ReadStatus read(nlohmann::json& message,
                    std::optional<std::chrono::milliseconds> timeout = std::nullopt);

    // Sends a request and waits for its reply; notifications meanwhile go to
    // `on_notification`. Empty when the connection closed or was interrupted
    // (looked at between reads and after every notification).
    // Throws Error (kTimeout) when no reply came within the call timeout
    // (plus kWaitAllowance for params with "wait": true); the connection
    // stays usable and the late reply is dropped.
    std::optional<nlohmann::json> call(
        const std::string& method, const nlohmann::json& params,
        const std::function<void(const nlohmann::json&)>& on_notification = {});

    // Calls `attitude_channel` and maps the descriptors of its reply
    // (AttitudeChannel), or shares the mapping this connection already has
    // ("descriptors":0); throws Error: the daemon's, kBadReply for a block
    // that fails its checks or a reply without the descriptors it
    // announced, kTransport when the connection is lost.
    AttitudeChannel attitude_channel(
        const std::function<void(const nlohmann::json&)>& on_notification = {});
    // The same for a caller that makes the call itself (send() or call()
    // of "attitude_channel"): the channel of its whole reply.
    AttitudeChannel channel_from(const nlohmann::json& reply) { return claims_.claim(reply); }

    // A descriptor (not owned; -1: none) that read() also polls: when it is
    // readable, read() returns kWoken.
    void watch(int fd) noexcept { watched_ = fd; }

    bool closed() const noexcept { return closed_; }
    void close() noexcept;

    // How long call() waits for a reply (and send() for gportd to take the
    // request); empty: no limit.
    void set_call_timeout(std::optional<std::chrono::milliseconds> timeout) noexcept {
        call_timeout_ = timeout;
    }
    std::optional<std::chrono::milliseconds> call_timeout() const noexcept { return call_timeout_; }
    // Why the library ended the connection (a line over a limit, not JSON, a
    // request gportd did not take in time); empty when it did not.
    const std::string& failure() const noexcept { return failure_; }

    // Checked between reads (set from a signal handler).
    std::function<bool()> interrupted = [] { return false; };

  private:
    explicit Connection(int fd) : fd_(fd) {}
    // Reads what arrived within the deadline; false when the watched
    // descriptor is readable.
    using Deadline = std::optional<std::chrono::steady_clock::time_point>;
    bool fill(Deadline deadline);
    void receive();
    std::optional<int> send(const std::string& method, const nlohmann::json& params,
                            Deadline deadline);
    bool write_all(std::string_view data, Deadline deadline);
    // Reads until the reply to request `id` (or a refusal) comes; the
    // deadline and interrupted() are looked at after every other message.
    std::optional<nlohmann::json> await_reply(
        int id, const std::string& method, std::optional<std::chrono::milliseconds> limit,
        Deadline deadline, const std::function<void(const nlohmann::json&)>& on_notification);
    // Ends the connection because of what gportd did.
    void fail(const std::string& why);

    int fd_ = -1;
    int next_id_ = 1;
    detail::LineReader lines_;
    bool closed_ = false;
    ChannelClaims claims_;  // received descriptors, attitude_channel requests, the channel
    int watched_ = -1;
    std::optional<std::chrono::milliseconds> call_timeout_ = kDefaultCallTimeout;
    std::string failure_;
};

}  // namespace gport::client
