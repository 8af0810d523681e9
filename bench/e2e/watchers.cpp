#include "watchers.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <string_view>
#include <thread>

#include "fake_gimbal.hpp"
#include "lines.hpp"
#include "nmea.hpp"

namespace gport::bench {
namespace {

constexpr std::uint64_t kGpsdKey = std::uint64_t{1} << 32;
constexpr std::string_view kWatch = "?WATCH={\"enable\":true,\"json\":true}\n";

// A blocking TCP connect to 127.0.0.1:port, retried while gpsd starts; the
// socket is made non-blocking afterwards (TCP_NODELAY: gpsd's side has it too).
Fd connect_tcp_retry(int port, int timeout_ms) {
    const auto deadline = now_ns() + std::int64_t{timeout_ms} * 1'000'000;
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<std::uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    for (;;) {
        Fd fd(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0));
        if (::connect(fd.get(), reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0) {
            const int one = 1;
            ::setsockopt(fd.get(), IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
            ::fcntl(fd.get(), F_SETFL, ::fcntl(fd.get(), F_GETFL) | O_NONBLOCK);
            return fd;
        }
        if (now_ns() > deadline) {
            throw std::runtime_error("gpsd did not accept on 127.0.0.1:" + std::to_string(port) +
                                     ": " + std::strerror(errno));
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
}

}  // namespace

WatchHub::WatchHub() : epoll_(::epoll_create1(EPOLL_CLOEXEC)) {
    if (!epoll_.valid()) {
        throw std::runtime_error(std::string("epoll_create1: ") + std::strerror(errno));
    }
}

void WatchHub::watch(int fd, std::uint64_t key) {
    epoll_event ev{};
    ev.events = EPOLLIN;
    ev.data.u64 = key;
    if (::epoll_ctl(epoll_.get(), EPOLL_CTL_ADD, fd, &ev) != 0) {
        throw std::runtime_error(std::string("epoll_ctl: ") + std::strerror(errno));
    }
}

void WatchHub::add_gportd(const std::string& socket, int count, int timeout_ms) {
    gportd_.reserve(static_cast<std::size_t>(count));
    for (int i = 0; i < count; ++i) {
        auto fd = i == 0 ? connect_unix_retry(socket, timeout_ms) : connect_unix(socket);
        if (!fd) {
            throw std::runtime_error("gportd did not accept on " + socket);
        }
        auto& s = gportd_.emplace_back();
        s.fd = std::move(*fd);
        watch(s.fd.get(), gportd_.size() - 1);
        if (!write_all(s.fd.get(), kSubscribeAttitude)) {
            throw std::runtime_error("gportd watcher " + std::to_string(i) + ": subscribe failed");
        }
    }
}

void WatchHub::add_gpsd(int port, int count, int timeout_ms) {
    gpsd_.reserve(static_cast<std::size_t>(count));
    for (int i = 0; i < count; ++i) {
        auto& s = gpsd_.emplace_back();
        s.fd = connect_tcp_retry(port, timeout_ms);
        watch(s.fd.get(), kGpsdKey + gpsd_.size() - 1);
        if (!write_all(s.fd.get(), kWatch)) {
            throw std::runtime_error("gpsd watcher " + std::to_string(i) + ": ?WATCH failed");
        }
    }
}

bool WatchHub::all_ready() const {
    for (const auto* group : {&gportd_, &gpsd_}) {
        for (const auto& s : *group) {
            if (!s.subscribed) {
                return false;
            }
        }
    }
    return true;
}

void WatchHub::wait_ready(int timeout_ms) {
    const auto deadline = now_ns() + std::int64_t{timeout_ms} * 1'000'000;
    while (!all_ready()) {
        if (now_ns() > deadline) {
            throw std::runtime_error("not every watcher got its subscribe or WATCH reply");
        }
        poll_once(50);
    }
}

void WatchHub::run_for(int duration_ms) {
    const auto end = now_ns() + std::int64_t{duration_ms} * 1'000'000;
    for (auto now = now_ns(); now < end; now = now_ns()) {
        poll_once(static_cast<int>((end - now) / 1'000'000) + 1);
    }
}

void WatchHub::poll_once(int timeout_ms) {
    epoll_event events[256];
    const int n = ::epoll_wait(epoll_.get(), events, 256, timeout_ms);
    for (int i = 0; i < n; ++i) {
        const auto key = events[i].data.u64;
        const bool is_gpsd = key >= kGpsdKey;
        auto& s = is_gpsd ? gpsd_[key - kGpsdKey] : gportd_[key];
        on_readable(s, is_gpsd);
    }
}

// Reads what is there; every complete line gets the time its read() returned.
void WatchHub::on_readable(Subscriber& s, bool is_gpsd) {
    char buffer[16384];
    for (;;) {
        const auto got = ::read(s.fd.get(), buffer, sizeof buffer);
        const auto t = now_ns();
        if (got <= 0) {
            if (got == 0 || (errno != EAGAIN && errno != EINTR)) {
                s.closed = true;
                ::epoll_ctl(epoll_.get(), EPOLL_CTL_DEL, s.fd.get(), nullptr);
            }
            return;
        }
        s.pending.append(buffer, static_cast<std::size_t>(got));
        std::size_t start = 0;
        for (auto nl = s.pending.find('\n'); nl != std::string::npos;
             nl = s.pending.find('\n', start)) {
            const std::string_view line(s.pending.data() + start, nl - start);
            const auto counter = is_gpsd ? counter_of_gpsd_line(line) : counter_of_line(line);
            if (counter != 0) {
                if (!s.receipts.empty() && counter <= s.receipts.back().counter) {
                    ++s.out_of_order;
                }
                s.receipts.push_back({counter, t});
            } else if (line.find(is_gpsd ? "\"class\":\"WATCH\"" : "\"id\":1") !=
                       std::string_view::npos) {
                s.subscribed = true;
            }
            start = nl + 1;
        }
        s.pending.erase(0, start);
    }
}

}  // namespace gport::bench
