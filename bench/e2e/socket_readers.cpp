#include "socket_readers.hpp"

#include <fcntl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <stdexcept>
#include <string_view>

#include "fake_gimbal.hpp"
#include "lines.hpp"

namespace gport::bench {
namespace {

// Blocking reads that give up after 100 ms, so a stop is noticed.
void make_blocking(int fd) {
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    timeval timeout{0, 100'000};
    ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof(timeout));
}

}  // namespace

struct SocketReaders::Reader {
    Fd fd;
    std::string pending;
    Subscriber result;
    std::atomic<bool> subscribed{false};
    std::atomic<std::uint32_t> last_seen{0};  // for caught_up() on another thread
    std::atomic<bool> closed{false};
};

SocketReaders::SocketReaders(const std::string& socket, int count, std::size_t expected_lines) {
    for (int i = 0; i < count; ++i) {
        auto reader = std::make_unique<Reader>();
        reader->fd = connect_unix(socket);
        make_blocking(reader->fd.get());
        reader->result.receipts.reserve(expected_lines + 16);
        if (!write_all(reader->fd.get(), kSubscribeAttitude)) {
            throw std::runtime_error("socket reader " + std::to_string(i) + ": subscribe failed");
        }
        readers_.push_back(std::move(reader));
    }
    for (auto& reader : readers_) {
        threads_.emplace_back([this, r = reader.get()] { run(*r); });
    }
    const auto deadline = now_ns() + 60'000'000'000LL;
    for (auto& reader : readers_) {
        while (!reader->subscribed.load()) {
            if (now_ns() > deadline) {
                throw std::runtime_error("socket readers did not all get their subscribe reply");
            }
            ::usleep(1000);
        }
    }
}

SocketReaders::~SocketReaders() {
    stop();
}

void SocketReaders::stop() {
    stop_ = true;
    for (auto& thread : threads_) {
        thread.join();
    }
    threads_.clear();
}

void SocketReaders::run(Reader& reader) {
    char buffer[65536];
    std::uint32_t last = 0;
    auto& out = reader.result;
    while (!stop_.load(std::memory_order_relaxed)) {
        const auto n = ::read(reader.fd.get(), buffer, sizeof(buffer));
        if (n < 0 && (errno == EAGAIN || errno == EINTR)) {
            continue;
        }
        if (n <= 0) {
            out.closed = true;
            reader.closed = true;
            return;
        }
        const auto t = now_ns();
        reader.pending.append(buffer, static_cast<std::size_t>(n));
        std::size_t start = 0;
        for (auto nl = reader.pending.find('\n'); nl != std::string::npos;
             nl = reader.pending.find('\n', start)) {
            const std::string_view line =
                std::string_view(reader.pending).substr(start, nl - start);
            start = nl + 1;
            if (line.find("\"method\":\"attitude\"") == std::string_view::npos) {
                reader.subscribed = true;
                continue;
            }
            const auto counter = counter_of_line(line);
            out.out_of_order += counter != 0 && counter <= last ? 1 : 0;
            last = counter != 0 ? counter : last;
            out.receipts.push_back({counter, t});
            out.reported_dropped = std::max(out.reported_dropped, dropped_field(line));
        }
        reader.pending.erase(0, start);
        reader.last_seen.store(last, std::memory_order_relaxed);
    }
}

bool SocketReaders::caught_up(std::uint32_t last) const {
    return std::all_of(readers_.begin(), readers_.end(), [last](const auto& reader) {
        return reader->closed.load() || reader->last_seen.load(std::memory_order_relaxed) >= last;
    });
}

std::vector<Subscriber> SocketReaders::take_results() {
    std::vector<Subscriber> results;
    for (auto& reader : readers_) {
        results.push_back(std::move(reader->result));
        results.back().subscribed = true;
    }
    return results;
}

}  // namespace gport::bench
