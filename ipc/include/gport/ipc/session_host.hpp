// What a Session needs from whoever runs it: the narrow seam between one
// connection and the server. Sessions see only this (session.* never
// includes server.hpp); the Server implements it, tests may fake it.
#pragma once

#include <array>
#include <cstddef>

namespace spdlog {
class logger;
}

namespace gport::config {
struct SocketConfig;
}

namespace gport::daemon {
struct ClientInfo;
}

namespace gport::ipc {

class Dispatcher;
class Session;

class SessionHost {
  public:
    // Runs each request line of every session.
    virtual Dispatcher& dispatcher() = 0;
    virtual const config::SocketConfig& config() const = 0;
    virtual spdlog::logger& log() = 0;

    // Attitude notifications this session lost, for the server's total.
    virtual void note_dropped(std::size_t count) = 0;
    // Closed for good: the core hears of it (client_gone unless the session
    // hung up earlier, then client_closed) on a later turn, never from inside
    // the event or callback that found the disconnect.
    virtual void session_closed(const Session& session) = 0;
    // EOF from the client: the deadman runs now; replies are still written.
    virtual void client_hung_up(const Session& session) = 0;

    // The memory budget across all sessions: each reports its queued bytes
    // as they change; over the budget, clients with unread output get no
    // more attitude samples and their requests wait.
    virtual void account(std::size_t before, std::size_t after) = 0;
    virtual bool over_budget() const = 0;

    // A client that holds control or owns a motion is never closed as idle.
    virtual bool holds_control_or_motion(const daemon::ClientInfo& client) const = 0;

    // The shared-memory attitude channel's descriptors for `client` (the
    // ring, its wake block), sent with the reply that says "descriptors":2;
    // -1s when there are none.
    virtual std::array<int, 2> channel_descriptors(const daemon::ClientInfo& client) const = 0;
    // That reply went out (error 0), or sendmsg refused the descriptors
    // (errno; the reply became -32603 and the next request sends them again).
    virtual void channel_delivered(const daemon::ClientInfo& client, int error) = 0;

  protected:
    SessionHost() = default;
    ~SessionHost() = default;
    SessionHost(const SessionHost&) = default;
    SessionHost& operator=(const SessionHost&) = default;
};

}  // namespace gport::ipc
