#include "line_probe.hpp"

#include <poll.h>
#include <unistd.h>

#include <array>
#include <stdexcept>

#include "posix.hpp"

namespace gport::bench {
namespace {

// Polls until `count()` passes `from`; false after `timeout_ms`.
template <typename Count>
bool wait_count_past(Count&& count, std::uint64_t from, int timeout_ms) {
    const auto deadline = now_ns() + std::int64_t{timeout_ms} * 1'000'000;
    while (count() <= from) {
        if (now_ns() > deadline) {
            return false;
        }
        ::usleep(200);
    }
    return true;
}

}  // namespace

LineStopProbe::LineStopProbe(std::string socket, const LineSim& sim, int stops, int period_ms)
    : socket_(std::move(socket)), sim_(sim), stops_(stops), period_ms_(period_ms) {}

LineStopProbe::~LineStopProbe() {
    join();
}

void LineStopProbe::start() {
    thread_ = std::thread([this] { run(); });
}

void LineStopProbe::join() {
    if (thread_.joinable()) {
        thread_.join();
    }
}

void LineStopProbe::run() {
    try {
        Fd fd = connect_unix(socket_);
        fd_ = fd.get();
        for (int i = 0; i < stops_; ++i) {
            const auto begin = now_ns();
            cycle(i);
            const auto used_ms = (now_ns() - begin) / 1'000'000;
            if (used_ms < period_ms_) {
                ::usleep(static_cast<useconds_t>((period_ms_ - used_ms) * 1000));
            }
        }
    } catch (const std::exception& e) {
        error_ = e.what();
    }
    fd_ = -1;
}

// A request and its reply (whatever notification comes first is skipped).
std::string LineStopProbe::call(const std::string& method, const std::string& params) {
    const std::string text = R"({"id":7,"method":")" + method + R"(","params":)" + params + "}\n";
    if (!write_all(fd_, text, 10'000)) {
        throw std::runtime_error("line probe: cannot send " + method);
    }
    std::string line;
    do {
        if (!read_line(fd_, pending_, line, 30'000)) {
            throw std::runtime_error("line probe: no reply to " + method);
        }
    } while (line.find(R"("id":7)") == std::string::npos);
    return line;
}

// Start a motion, see it on the wire, let it run 100 ms, stop it: the delay
// runs from the stop's write() to the zero speed's last byte at line rate.
void LineStopProbe::cycle(int) {
    const auto moving = sim_.speeds_seen();
    const auto reply = call("speed", R"({"yaw":10,"duration_ms":60000})");
    if (reply.find("\"result\"") == std::string::npos) {
        throw std::runtime_error("line probe: speed refused: " + reply);
    }
    if (!wait_count_past([this] { return sim_.speeds_seen(); }, moving, kLineStopTimeoutMs)) {
        throw std::runtime_error("line probe: the speed never reached the gimbal");
    }
    ::usleep(100'000);
    const auto stops = sim_.stops_seen();
    const std::string stop = R"({"id":8,"method":"stop"})"
                             "\n";
    if (!write_all(fd_, stop, 10'000)) {
        throw std::runtime_error("line probe: cannot send stop");
    }
    const auto sent = now_ns();
    if (!wait_count_past([this] { return sim_.stops_seen(); }, stops, kLineStopTimeoutMs)) {
        ++lost_;
    } else {
        delays_.push_back(static_cast<double>(sim_.stop_time(stops) - sent) / 1e6);
    }
    std::string line;
    do {
        if (!read_line(fd_, pending_, line, 30'000)) {
            throw std::runtime_error("line probe: no reply to stop");
        }
    } while (line.find(R"("id":8)") == std::string::npos);
}

AttitudeWatch::AttitudeWatch(const std::string& socket) {
    Fd fd = connect_unix(socket);
    const std::string subscribe =
        R"({"id":1,"method":"subscribe","params":{"topics":["attitude"]}})"
        "\n";
    if (!write_all(fd.get(), subscribe)) {
        throw std::runtime_error("attitude watch: cannot subscribe");
    }
    fd_ = fd.release();
    thread_ = std::thread([this] { run(); });
}

AttitudeWatch::~AttitudeWatch() {
    stop();
}

void AttitudeWatch::stop() {
    running_ = false;
    if (thread_.joinable()) {
        thread_.join();
    }
    if (fd_ >= 0) {
        ::close(fd_);
        fd_ = -1;
    }
}

double AttitudeWatch::longest_gap_ms() const {
    const auto tail = last_ns_.load() > 0 ? now_ns() - last_ns_.load() : 0;
    return static_cast<double>(std::max(longest_ns_.load(), tail)) / 1e6;
}

// Counts notification lines by their method; a line may span reads.
void AttitudeWatch::run() {
    std::array<char, 65536> buf{};
    std::string line;
    while (running_) {
        pollfd p{fd_, POLLIN, 0};
        if (::poll(&p, 1, 50) <= 0) {
            continue;
        }
        const auto n = ::read(fd_, buf.data(), buf.size());
        if (n <= 0) {
            return;
        }
        const auto t = now_ns();
        if (restart_.exchange(false)) {
            longest_ns_ = 0;
            last_ns_ = t;
        }
        for (ssize_t i = 0; i < n; ++i) {
            const char c = buf[static_cast<std::size_t>(i)];
            if (c != '\n') {
                line += c;
                continue;
            }
            if (line.find(R"("method":"attitude")") != std::string::npos) {
                if (last_ns_ > 0) {
                    longest_ns_ = std::max(longest_ns_.load(), t - last_ns_.load());
                }
                last_ns_ = t;
                ++lines_;
            }
            line.clear();
        }
    }
}

}  // namespace gport::bench
