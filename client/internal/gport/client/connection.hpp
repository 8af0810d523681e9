// The transport under Client and gportctl: newline-delimited JSON-RPC over
// gportd's Unix socket, blocking, plain POSIX. Notifications that arrive
// while waiting for a reply go to a handler; reads give up when
// `interrupted()` turns true.
//
// Internal to the project (not installed): its symbols are exported from
// libgport-client for gportctl, but its interface may change in any release.
#pragma once

#include <chrono>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "gport/client/export.hpp"

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

    // Sends a request (with a fresh id) and returns the id; empty on a broken connection.
    std::optional<int> send(const std::string& method, const nlohmann::json& params);

    enum class ReadStatus { kMessage, kTimeout, kClosed, kInterrupted };
    // The next message; waits at most `timeout` (forever when empty).
    ReadStatus read(nlohmann::json& message,
                    std::optional<std::chrono::milliseconds> timeout = std::nullopt);

    // Sends a request and waits for its reply; notifications meanwhile go to
    // `on_notification`. Empty when the connection closed or was interrupted.
    std::optional<nlohmann::json> call(
        const std::string& method, const nlohmann::json& params,
        const std::function<void(const nlohmann::json&)>& on_notification = {});

    bool closed() const noexcept { return closed_; }
    void close() noexcept;

    // Checked between reads (set from a signal handler).
    std::function<bool()> interrupted = [] { return false; };

  private:
    explicit Connection(int fd) : fd_(fd) {}
    void fill(std::optional<std::chrono::steady_clock::time_point> deadline);

    int fd_ = -1;
    int next_id_ = 1;
    std::string buffer_;
    bool closed_ = false;
};

}  // namespace gport::client
