// Test helpers: a PtySimulator running on its own thread, and a client that
// opens the slave side and reads it with generous timeouts.
#pragma once

#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <unistd.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <chrono>
#include <cstdint>
#include <future>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "gport/protocol/decoder.hpp"
#include "gport/protocol/messages.hpp"
#include "gport/sim/simulator.hpp"

namespace gport::sim::testing {

using namespace std::chrono_literals;

// The simulator on a background io_context; trace lines are collected.
class SimThread {
  public:
    explicit SimThread(SimOptions options) {
        options.trace = [this](const std::string& line) {
            std::lock_guard lock(mutex_);
            trace_.push_back(line);
        };
        sim_ = std::make_unique<PtySimulator>(io_, std::move(options));
        path_ = sim_->device_path();
        thread_ = std::thread([this] { io_.run(); });
    }
    ~SimThread() { stop(); }

    const std::string& path() const { return path_; }
    void stop() {
        if (thread_.joinable()) {
            boost::asio::post(io_, [this] { sim_->stop(); });
            thread_.join();
        }
    }
    // Runs f on the simulator's thread and returns its result.
    template <typename F>
    auto on_io(F f) {
        std::packaged_task<decltype(f(*sim_))()> task([&] { return f(*sim_); });
        auto result = task.get_future();
        boost::asio::post(io_, [&] { task(); });
        return result.get();
    }
    SimStats stats() {
        return on_io([](PtySimulator& s) { return s.stats(); });
    }
    std::vector<std::string> trace() {
        std::lock_guard lock(mutex_);
        return trace_;
    }
    bool traced(const std::string& needle) {
        for (const auto& line : trace()) {
            if (line.find(needle) != std::string::npos) {
                return true;
            }
        }
        return false;
    }

  private:
    boost::asio::io_context io_;
    std::unique_ptr<PtySimulator> sim_;
    std::string path_;
    std::thread thread_;
    std::mutex mutex_;
    std::vector<std::string> trace_;
};

// Polls `pred` until it holds or `timeout` passes.
template <typename Pred>
bool eventually(Pred pred, std::chrono::milliseconds timeout = 5000ms) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < end) {
        if (pred()) {
            return true;
        }
        std::this_thread::sleep_for(5ms);
    }
    return pred();
}

// The client side: the slave, opened as gportd opens its serial port.
class Client {
  public:
    explicit Client(const std::string& path)
        : fd_(::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC)) {}
    ~Client() { close(); }
    Client(const Client&) = delete;
    Client& operator=(const Client&) = delete;

    bool ok() const { return fd_ >= 0; }
    int fd() const { return fd_; }
    void close() {
        if (fd_ >= 0) {
            ::close(fd_);
            fd_ = -1;
        }
    }
    void write(std::span<const std::uint8_t> bytes) {
        ASSERT_EQ(::write(fd_, bytes.data(), bytes.size()), static_cast<ssize_t>(bytes.size()));
    }
    // One non-blocking write; what ::write returned (-1 with EAGAIN when full).
    ssize_t try_write(std::span<const std::uint8_t> bytes) {
        return ::write(fd_, bytes.data(), bytes.size());
    }
    void send(const protocol::Message& m) {
        const auto f = protocol::encode(m);
        write(f.bytes());
    }

    // Reads for `how_long`; stops early on EOF/EIO (sets failed()).
    std::vector<std::uint8_t> read_for(std::chrono::milliseconds how_long) {
        std::vector<std::uint8_t> out;
        const auto end = std::chrono::steady_clock::now() + how_long;
        while (!failed_) {
            const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                end - std::chrono::steady_clock::now());
            if (left <= 0ms) {
                break;
            }
            pollfd p{fd_, POLLIN, 0};
            if (::poll(&p, 1, static_cast<int>(left.count())) <= 0) {
                continue;
            }
            std::uint8_t buf[4096];
            const auto n = ::read(fd_, buf, sizeof buf);
            if (n > 0) {
                out.insert(out.end(), buf, buf + n);
                read_sizes_.push_back(static_cast<std::size_t>(n));
                last_read_ = std::chrono::steady_clock::now();
                read_times_.push_back(last_read_);
            } else if (n == 0 || (errno != EAGAIN && errno != EINTR)) {
                failed_ = true;
            }
        }
        return out;
    }
    bool failed() const { return failed_; }
    const std::vector<std::size_t>& read_sizes() const { return read_sizes_; }
    const std::vector<std::chrono::steady_clock::time_point>& read_times() const {
        return read_times_;
    }

  private:
    int fd_ = -1;
    bool failed_ = false;
    std::vector<std::size_t> read_sizes_;
    std::vector<std::chrono::steady_clock::time_point> read_times_;
    std::chrono::steady_clock::time_point last_read_;
};

// Decodes bytes the way gportd does: frames and decoder counters.
struct Decoded {
    std::vector<protocol::Message> messages;
    protocol::DecoderStats stats;

    std::vector<protocol::Attitude> attitudes() const {
        std::vector<protocol::Attitude> out;
        for (const auto& m : messages) {
            if (const auto* a = std::get_if<protocol::Attitude>(&m)) {
                out.push_back(*a);
            }
        }
        return out;
    }
};

inline Decoded decode_all(std::span<const std::uint8_t> bytes) {
    Decoded d;
    protocol::Decoder decoder;
    decoder.feed(bytes, [&](const protocol::FrameView& f) {
        if (auto m = protocol::decode(f)) {
            d.messages.push_back(*m);
        }
    });
    d.stats = decoder.stats();
    return d;
}

}  // namespace gport::sim::testing
