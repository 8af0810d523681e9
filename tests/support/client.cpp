#include "client.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstring>
#include <stdexcept>
#include <thread>

namespace gport::testing {

namespace {

int connect_once(const std::string& path) {
    const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    std::strncpy(addr.sun_path, path.c_str(), sizeof addr.sun_path - 1);
    if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
        ::close(fd);
        return -1;
    }
    return fd;
}

}  // namespace

Client::Client(const std::string& socket_path, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while ((fd_ = connect_once(socket_path)) < 0 && std::chrono::steady_clock::now() < deadline) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
}

Client::~Client() {
    close();
}

void Client::close() {
    if (fd_ >= 0) {
        ::close(fd_);
        fd_ = -1;
    }
}

void Client::send_line(const std::string& line) {
    std::string data = line + "\n";
    std::size_t off = 0;
    while (off < data.size()) {
        const ssize_t n = ::send(fd_, data.data() + off, data.size() - off, MSG_NOSIGNAL);
        if (n <= 0) {
            throw std::runtime_error("send to gportd failed");
        }
        off += static_cast<std::size_t>(n);
    }
}

std::optional<std::string> Client::read_line(std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
        const auto pos = buffer_.find('\n');
        if (pos != std::string::npos) {
            std::string line = buffer_.substr(0, pos);
            buffer_.erase(0, pos + 1);
            return line;
        }
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
            deadline - std::chrono::steady_clock::now());
        if (fd_ < 0 || left.count() <= 0) {
            return std::nullopt;
        }
        pollfd p{fd_, POLLIN, 0};
        if (::poll(&p, 1, static_cast<int>(left.count())) <= 0) {
            continue;
        }
        char buf[65536];
        const ssize_t n = ::recv(fd_, buf, sizeof buf, 0);
        if (n <= 0) {
            close();
            return std::nullopt;
        }
        buffer_.append(buf, static_cast<std::size_t>(n));
    }
}

std::optional<Json> Client::read(std::chrono::milliseconds timeout) {
    auto line = read_line(timeout);
    if (!line) {
        return std::nullopt;
    }
    return Json::parse(*line);
}

Json Client::call(const std::string& method, const Json& params,
                  std::chrono::milliseconds timeout) {
    const long id = next_id_++;
    Json request{{"jsonrpc", "2.0"}, {"id", id}, {"method", method}};
    if (!params.is_null()) {
        request["params"] = params;
    }
    send_line(request.dump());
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
            deadline - std::chrono::steady_clock::now());
        auto reply = read(left);
        if (!reply) {
            throw std::runtime_error("no reply from gportd to " + method);
        }
        if (reply->contains("id") && (*reply)["id"] == id) {
            return *reply;
        }
        if (reply->contains("method")) {
            notifications_.push_back(*reply);
        }
    }
}

std::optional<Json> Client::notification(const std::string& method,
                                         std::chrono::milliseconds timeout) {
    for (auto it = notifications_.begin(); it != notifications_.end(); ++it) {
        if ((*it)["method"] == method) {
            Json n = *it;
            notifications_.erase(it);
            return n;
        }
    }
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
            deadline - std::chrono::steady_clock::now());
        auto msg = read(left);
        if (!msg) {
            return std::nullopt;
        }
        if (msg->value("method", "") == method) {
            return msg;
        }
        if (msg->contains("method")) {
            notifications_.push_back(*msg);
        }
    }
}

bool Client::closed_by_peer(std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (fd_ >= 0 && std::chrono::steady_clock::now() < deadline) {
        read_line(std::chrono::milliseconds(50));
    }
    return fd_ < 0;
}

}  // namespace gport::testing
