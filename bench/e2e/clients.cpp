#include "clients.hpp"

#include <sys/epoll.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string_view>

#include "fake_gimbal.hpp"
#include "lines.hpp"

namespace gport::bench {
namespace {

// Epoll keys: subscribers are 0..N-1, flooders are offset by this.
constexpr std::uint64_t kFlooderKey = 1ULL << 32;

// Reads everything available; calls on_line(line, t) for each whole line,
// with t the time the read() that completed it returned. False on EOF/error.
template <typename OnLine>
bool drain(int fd, std::string& pending, OnLine&& on_line) {
    char buffer[65536];
    while (true) {
        const auto n = ::read(fd, buffer, sizeof(buffer));
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n < 0 && errno == EAGAIN) {
            return true;
        }
        if (n <= 0) {
            return false;
        }
        const auto t = now_ns();
        pending.append(buffer, static_cast<std::size_t>(n));
        std::size_t start = 0;
        for (auto nl = pending.find('\n'); nl != std::string::npos;
             nl = pending.find('\n', start)) {
            on_line(std::string_view(pending).substr(start, nl - start), t);
            start = nl + 1;
        }
        pending.erase(0, start);
    }
}

}  // namespace

ClientHub::ClientHub() : epoll_(::epoll_create1(EPOLL_CLOEXEC)) {
    if (!epoll_.valid()) {
        throw std::runtime_error(std::string("epoll_create1: ") + std::strerror(errno));
    }
}

void ClientHub::watch(int fd, std::uint64_t key) {
    epoll_event event{};
    event.events = EPOLLIN | EPOLLRDHUP;
    event.data.u64 = key;
    if (::epoll_ctl(epoll_.get(), EPOLL_CTL_ADD, fd, &event) != 0) {
        throw std::runtime_error(std::string("epoll_ctl: ") + std::strerror(errno));
    }
}

void ClientHub::add_subscribers(const std::string& socket, int count, int timeout_ms) {
    subscribers_.reserve(static_cast<std::size_t>(count));
    for (int i = 0; i < count; ++i) {
        auto& s = subscribers_.emplace_back();
        s.fd = connect_unix(socket);
        watch(s.fd.get(), subscribers_.size() - 1);
        if (!write_all(s.fd.get(), kSubscribeAttitude)) {
            throw std::runtime_error("subscriber " + std::to_string(i) + ": subscribe failed");
        }
    }
    const auto deadline = now_ns() + std::int64_t{timeout_ms} * 1'000'000;
    auto ready = [&] {
        for (const auto& s : subscribers_) {
            if (!s.subscribed) {
                return false;
            }
        }
        return true;
    };
    while (!ready()) {
        if (now_ns() > deadline) {
            throw std::runtime_error("subscribers did not all get their subscribe reply");
        }
        poll_once(50);
    }
}

void ClientHub::add_flooders(const std::string& socket, int count) {
    for (int i = 0; i < count; ++i) {
        auto& f = flooders_.emplace_back();
        f.fd = connect_unix(socket);
        watch(f.fd.get(), kFlooderKey + flooders_.size() - 1);
    }
}

void ClientHub::start_flood() {
    flooding_ = true;
    for (auto& f : flooders_) {
        send_request(f);
    }
}

void ClientHub::send_request(Flooder& f) {
    const auto line = R"({"id":)" + std::to_string(f.next_id++) + R"(,"method":"status"})" + "\n";
    if (!write_all(f.fd.get(), line, 1000)) {
        f.closed = true;
    }
}

void ClientHub::run_for(int duration_ms) {
    const auto end = now_ns() + std::int64_t{duration_ms} * 1'000'000;
    while (true) {
        const auto left_ms = (end - now_ns()) / 1'000'000;
        if (left_ms <= 0) {
            return;
        }
        poll_once(static_cast<int>(left_ms));
    }
}

void ClientHub::poll_once(int timeout_ms) {
    epoll_event events[512];
    const int n = ::epoll_wait(epoll_.get(), events, 512, timeout_ms);
    for (int i = 0; i < n; ++i) {
        const auto key = events[i].data.u64;
        if (key >= kFlooderKey) {
            on_flooder(flooders_[key - kFlooderKey]);
        } else {
            on_subscriber(subscribers_[key]);
        }
    }
}

void ClientHub::on_subscriber(Subscriber& s) {
    const bool open = drain(s.fd.get(), s.pending, [&](std::string_view line, std::int64_t t) {
        if (line.find("\"method\":\"attitude\"") == std::string_view::npos) {
            s.subscribed = s.subscribed || line.find("\"result\"") != std::string_view::npos;
            return;
        }
        const auto counter = counter_of_line(line);
        if (!s.receipts.empty() && counter <= s.receipts.back().counter) {
            ++s.out_of_order;
        }
        s.receipts.push_back({counter, t});
        if (const auto dropped = dropped_field(line); dropped > s.reported_dropped) {
            s.reported_dropped = dropped;
        }
    });
    if (!open && !s.closed) {
        s.closed = true;
        ::epoll_ctl(epoll_.get(), EPOLL_CTL_DEL, s.fd.get(), nullptr);
    }
}

void ClientHub::on_flooder(Flooder& f) {
    const bool open = drain(f.fd.get(), f.pending, [&](std::string_view, std::int64_t) {
        ++f.replies;
        if (flooding_ && !f.closed) {
            send_request(f);
        }
    });
    if (!open && !f.closed) {
        f.closed = true;
        ::epoll_ctl(epoll_.get(), EPOLL_CTL_DEL, f.fd.get(), nullptr);
    }
}

void ClientHub::adopt(std::vector<Subscriber> measured) {
    for (auto& s : measured) {
        subscribers_.push_back(std::move(s));
    }
}

bool ClientHub::caught_up(std::uint32_t last) const {
    return std::all_of(subscribers_.begin(), subscribers_.end(), [last](const Subscriber& s) {
        return s.closed || (!s.receipts.empty() && s.receipts.back().counter >= last);
    });
}

std::uint64_t ClientHub::flood_replies() const {
    std::uint64_t total = 0;
    for (const auto& f : flooders_) {
        total += f.replies;
    }
    return total;
}

}  // namespace gport::bench
