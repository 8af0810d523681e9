// Test support: a blocking JSON-RPC client for gportd's socket. Replies are
// matched by id; notifications that arrive meanwhile are kept for the test.
#pragma once

#include <chrono>
#include <deque>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace gport::testing {

using Json = nlohmann::json;

class Client {
  public:
    // Connects, retrying until the timeout (the daemon may still be starting).
    explicit Client(const std::string& socket_path,
                    std::chrono::milliseconds timeout = std::chrono::seconds(10));
    ~Client();
    Client(const Client&) = delete;
    Client& operator=(const Client&) = delete;

    bool connected() const { return fd_ >= 0; }
    void close();

    // Sends a request and returns the whole reply object (with result or error).
    Json call(const std::string& method, const Json& params = nullptr,
              std::chrono::milliseconds timeout = std::chrono::seconds(10));
    void send_line(const std::string& line);
    // The next line the daemon sent, parsed; empty on timeout or close.
    std::optional<Json> read(std::chrono::milliseconds timeout = std::chrono::seconds(10));
    // The next notification with this method (taking kept ones first).
    std::optional<Json> notification(const std::string& method,
                                     std::chrono::milliseconds timeout = std::chrono::seconds(10));
    // True once the daemon closed the connection (waits up to timeout).
    bool closed_by_peer(std::chrono::milliseconds timeout = std::chrono::seconds(5));

  private:
    std::optional<std::string> read_line(std::chrono::milliseconds timeout);

    int fd_ = -1;
    long next_id_ = 1;
    std::string buffer_;
    std::deque<Json> notifications_;
};

}  // namespace gport::testing
