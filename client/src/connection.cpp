#include "gport/client/connection.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <system_error>
#include <utility>

#include "connect_error.hpp"
#include "gport/client/error.hpp"

namespace gport::client {
namespace {

// Reads wake up this often to look at interrupted().
constexpr int kPollSliceMs = 100;

}  // namespace

Connection Connection::open(const std::string& path) {
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    if (path.empty() || path.size() >= sizeof(address.sun_path)) {
        throw Error(ErrorCode::kTransport,
                    "cannot connect to " + path + ": the path must be 1 to " +
                        std::to_string(sizeof(address.sun_path) - 1) + " bytes");
    }
    std::memcpy(address.sun_path, path.c_str(), path.size() + 1);
    const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) {
        throw Error(ErrorCode::kTransport,
                    std::string("cannot create a socket: ") + std::strerror(errno));
    }
    if (::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) != 0) {
        const int error = errno;
        ::close(fd);
        throw Error(ErrorCode::kTransport,
                    detail::connect_failure(path, error, std::strerror(error)));
    }
    return Connection(fd);
}

Connection::Connection(Connection&& other) noexcept
    : interrupted(std::move(other.interrupted)),
      fd_(std::exchange(other.fd_, -1)),
      next_id_(other.next_id_),
      buffer_(std::move(other.buffer_)),
      closed_(other.closed_) {}

Connection& Connection::operator=(Connection&& other) noexcept {
    if (this != &other) {
        if (fd_ >= 0) {
            ::close(fd_);
        }
        interrupted = std::move(other.interrupted);
        fd_ = std::exchange(other.fd_, -1);
        next_id_ = other.next_id_;
        buffer_ = std::move(other.buffer_);
        closed_ = other.closed_;
    }
    return *this;
}

Connection::~Connection() {
    close();
}

void Connection::close() noexcept {
    if (fd_ >= 0) {
        ::close(fd_);
        fd_ = -1;
    }
    closed_ = true;
}

std::optional<int> Connection::send(const std::string& method, const nlohmann::json& params) {
    if (fd_ < 0) {
        return std::nullopt;
    }
    const int id = next_id_++;
    nlohmann::json request = {{"jsonrpc", "2.0"}, {"id", id}, {"method", method}};
    if (!params.empty()) {
        request["params"] = params;
    }
    const std::string line = request.dump() + "\n";
    std::string_view left = line;
    while (!left.empty()) {
        const auto n = ::send(fd_, left.data(), left.size(), MSG_NOSIGNAL);
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n <= 0) {
            closed_ = true;
            return std::nullopt;
        }
        left.remove_prefix(static_cast<std::size_t>(n));
    }
    return id;
}

void Connection::fill(std::optional<std::chrono::steady_clock::time_point> deadline) {
    int wait = kPollSliceMs;
    if (deadline) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                              *deadline - std::chrono::steady_clock::now())
                              .count();
        wait = static_cast<int>(std::clamp<long long>(left, 0, kPollSliceMs));
    }
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, wait) <= 0) {
        return;  // nothing yet (or EINTR): the caller checks the clock and signals
    }
    char chunk[65536];
    const auto n = ::recv(fd_, chunk, sizeof(chunk), 0);
    if (n < 0 && errno == EINTR) {
        return;
    }
    if (n <= 0) {
        closed_ = true;
        return;
    }
    buffer_.append(chunk, static_cast<std::size_t>(n));
}

Connection::ReadStatus Connection::read(nlohmann::json& message,
                                        std::optional<std::chrono::milliseconds> timeout) {
    std::optional<std::chrono::steady_clock::time_point> deadline;
    if (timeout) {
        deadline = std::chrono::steady_clock::now() + *timeout;
    }
    bool polled = false;  // a zero timeout still looks at the socket once
    while (true) {
        if (auto nl = buffer_.find('\n'); nl != std::string::npos) {
            const std::string line = buffer_.substr(0, nl);
            buffer_.erase(0, nl + 1);
            message = nlohmann::json::parse(line, nullptr, false);
            if (!message.is_discarded()) {
                return ReadStatus::kMessage;
            }
            continue;  // not JSON: not from gportd; skip it
        }
        if (closed_) {
            return ReadStatus::kClosed;
        }
        if (interrupted()) {
            return ReadStatus::kInterrupted;
        }
        if (polled && deadline && std::chrono::steady_clock::now() >= *deadline) {
            return ReadStatus::kTimeout;
        }
        fill(deadline);
        polled = true;
    }
}

std::optional<nlohmann::json> Connection::call(
    const std::string& method, const nlohmann::json& params,
    const std::function<void(const nlohmann::json&)>& on_notification) {
    const auto id = send(method, params);
    if (!id) {
        return std::nullopt;
    }
    nlohmann::json message;
    while (read(message) == ReadStatus::kMessage) {
        if (message.contains("id")) {
            if (message["id"] == *id || message["id"].is_null()) {
                return message;  // null id: the daemon refused us (e.g. too many clients)
            }
        } else if (on_notification) {
            on_notification(message);
        }
    }
    return std::nullopt;
}

}  // namespace gport::client
