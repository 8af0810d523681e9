// A blocking Unix-socket client for tests: send text, read lines with a
// generous timeout, detect the server closing the connection.
#pragma once

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

#include "unix_connect.hpp"

namespace gport::testing {

using namespace std::chrono_literals;

class TestClient {
  public:
    explicit TestClient(const std::string& path) { fd_ = connect_unix(path); }
    ~TestClient() { disconnect(); }
    TestClient(const TestClient&) = delete;
    TestClient& operator=(const TestClient&) = delete;

    bool connected() const { return fd_ >= 0; }
    void disconnect() {
        if (fd_ >= 0) {
            ::close(fd_);
            fd_ = -1;
        }
    }

    // Half-close: no more requests, replies still readable.
    void shutdown_write() { ::shutdown(fd_, SHUT_WR); }

    // False once the server has closed the connection.
    bool send(std::string_view text) {
        while (!text.empty()) {
            const auto n = ::send(fd_, text.data(), text.size(), MSG_NOSIGNAL);
            if (n <= 0) {
                return false;
            }
            text.remove_prefix(static_cast<std::size_t>(n));
        }
        return true;
    }

    // The next line without its '\n'; empty when none came in time or the
    // connection closed.
    std::optional<std::string> line(std::chrono::milliseconds timeout = 10s) {
        const auto deadline = std::chrono::steady_clock::now() + timeout;
        while (true) {
            if (auto nl = buffer_.find('\n'); nl != std::string::npos) {
                auto out = buffer_.substr(0, nl);
                buffer_.erase(0, nl + 1);
                return out;
            }
            if (!fill(deadline)) {
                return std::nullopt;
            }
        }
    }

    nlohmann::json next(std::chrono::milliseconds timeout = 10s) {
        auto text = line(timeout);
        return text ? nlohmann::json::parse(*text) : nlohmann::json();
    }

    // Sends a request and returns its reply, skipping notifications.
    nlohmann::json call(std::string_view method, nlohmann::json params = nullptr) {
        const int id = ++id_;
        nlohmann::json request = {{"id", id}, {"method", method}};
        if (!params.is_null()) {
            request["params"] = std::move(params);
        }
        send(request.dump() + "\n");
        while (true) {
            auto reply = next();
            if (reply.is_null() || (reply.contains("id") && reply["id"] == id)) {
                return reply;
            }
        }
    }

    // True when the server closed the connection within `timeout` (lines
    // still in flight are read and discarded).
    bool closed_by_server(std::chrono::milliseconds timeout = 10s) {
        const auto deadline = std::chrono::steady_clock::now() + timeout;
        while (fill(deadline)) {
            buffer_.clear();
        }
        return eof_;
    }

  private:
    bool fill(std::chrono::steady_clock::time_point deadline) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
            deadline - std::chrono::steady_clock::now());
        if (fd_ < 0 || eof_ || left.count() <= 0) {
            return false;
        }
        pollfd p{fd_, POLLIN, 0};
        if (::poll(&p, 1, static_cast<int>(left.count())) <= 0) {
            return false;
        }
        char chunk[65536];
        const auto n = ::recv(fd_, chunk, sizeof(chunk), 0);
        if (n <= 0) {
            eof_ = true;
            return false;
        }
        buffer_.append(chunk, static_cast<std::size_t>(n));
        return true;
    }

    int fd_ = -1;
    int id_ = 0;
    bool eof_ = false;
    std::string buffer_;
};

}  // namespace gport::testing
