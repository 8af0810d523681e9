#include "stop_pinger.hpp"

#include <fmt/format.h>
#include <pthread.h>
#include <sched.h>

#include <ctime>
#include <stdexcept>
#include <utility>

#include "lines.hpp"
#include "posix.hpp"

namespace gport::bench {

StopPinger::StopPinger(std::string socket, int period_ms)
    : socket_(std::move(socket)), period_ms_(period_ms) {}

StopPinger::~StopPinger() {
    stop();
}

void StopPinger::start() {
    rtt_ns_.reserve(100000);
    thread_ = std::thread([this] { run(); });
}

void StopPinger::stop() {
    stop_ = true;
    if (thread_.joinable()) {
        thread_.join();
    }
}

void StopPinger::run() {
    sched_param param{};
    param.sched_priority = 10;
    ::pthread_setschedparam(::pthread_self(), SCHED_FIFO, &param);
    try {
        Fd fd = connect_unix(socket_);
        std::string pending;
        std::uint64_t id = 1;
        auto next = now_ns();
        while (!stop_) {
            next += std::int64_t{period_ms_} * 1'000'000;
            const std::string request = R"({"id":)" + std::to_string(id++) + R"(,"method":"stop"})";
            const auto before = now_ns();
            if (!write_all(fd.get(), request + "\n")) {
                throw std::runtime_error("stop pinger: cannot send stop");
            }
            std::string line;
            if (!read_line(fd.get(), pending, line, 5000)) {
                ++lost_;
                throw std::runtime_error("stop pinger: no reply to stop within 5 s");
            }
            rtt_ns_.push_back(now_ns() - before);
            const timespec at{static_cast<time_t>(next / 1'000'000'000), next % 1'000'000'000};
            while (::clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &at, nullptr) == EINTR) {
            }
        }
    } catch (const std::exception& e) {
        error_ = e.what();
    }
}

PingStats StopPinger::stats() const {
    PingStats s;
    std::vector<double> ms;
    for (const auto ns : rtt_ns_) {
        ms.push_back(static_cast<double>(ns) / 1e6);
    }
    s.count = ms.size();
    s.lost = lost_;
    if (!ms.empty()) {
        s.p50_ms = quantile(ms, 0.50);
        s.p99_ms = quantile(ms, 0.99);
        s.max_ms = quantile(ms, 1.0);
    }
    return s;
}

std::string ping_line(const PingStats& s, int period_ms) {
    return fmt::format(
        "  stop round trip (every {} ms) | n {:>5} | lost {} | p50 {:>7.3f} ms | p99 {:>7.3f} ms | "
        "max {:>8.3f} ms\n",
        period_ms, s.count, s.lost, s.p50_ms, s.p99_ms, s.max_ms);
}

nlohmann::json to_json(const PingStats& s) {
    return {{"count", s.count},
            {"lost", s.lost},
            {"p50_ms", s.p50_ms},
            {"p99_ms", s.p99_ms},
            {"max_ms", s.max_ms}};
}

}  // namespace gport::bench
