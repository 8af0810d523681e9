#include "stop_probe.hpp"

#include <pthread.h>
#include <sched.h>
#include <unistd.h>

#include <ctime>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <utility>

namespace gport::bench {
namespace {

void sleep_until(std::int64_t at_ns) {
    const timespec at{static_cast<time_t>(at_ns / 1'000'000'000), at_ns % 1'000'000'000};
    while (::clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &at, nullptr) == EINTR) {
    }
}

// Polls `count` (the fake gimbal's reader bumps it) until it passes `from`;
// false after `timeout_ms`. The stamps come from the reader, so the poll's
// period only decides when the probe moves on.
template <typename Count>
bool wait_past(Count&& count, std::uint64_t from, int timeout_ms) {
    const auto deadline = now_ns() + std::int64_t{timeout_ms} * 1'000'000;
    while (count() <= from) {
        if (now_ns() > deadline) {
            return false;
        }
        ::usleep(100);
    }
    return true;
}

}  // namespace

StopProbe::StopProbe(std::string socket, const FakeGimbal& gimbal, int per_cause, double seconds)
    : socket_(std::move(socket)), gimbal_(gimbal), per_cause_(per_cause), seconds_(seconds) {}

StopProbe::~StopProbe() {
    join();
}

void StopProbe::start() {
    thread_ = std::thread([this] { run(); });
}

void StopProbe::join() {
    if (thread_.joinable()) {
        thread_.join();
    }
}

// SCHED_FIFO when allowed, like the fake gimbal's threads: a cause is
// stamped when the write() returns, not when a busy machine gets round to it.
void StopProbe::run() {
    sched_param param{};
    param.sched_priority = 10;
    ::pthread_setschedparam(::pthread_self(), SCHED_FIFO, &param);
    const int cycles = 2 * per_cause_;
    const auto period_ns = static_cast<std::int64_t>(seconds_ * 1e9 / cycles);
    const auto start_ns = now_ns();
    try {
        for (int i = 0; i < cycles; ++i) {
            cycle(i, start_ns + i * period_ns, period_ns);
        }
    } catch (const std::exception& e) {
        error_ = e.what();
    }
    fd_.reset();
}

// One motion: start it, let it run for three quarters of the cycle (long
// enough for a keepalive at 10 Hz once cycles reach 133 ms), end it (even
// cycles by `stop`, odd ones by closing), and wait for the zero speed.
void StopProbe::cycle(int index, std::int64_t start_ns, std::int64_t period_ns) {
    sleep_until(start_ns);
    if (!fd_.valid()) {
        fd_ = connect_unix(socket_);
        pending_.clear();
    }
    start_motion();
    sleep_until(start_ns + period_ns * 3 / 4);
    end_motion(index % 2 == 0 ? StopCause::kStopRequest : StopCause::kDisconnect);
}

void StopProbe::start_motion() {
    const int duration_ms = static_cast<int>(seconds_ * 1000) + 10000;
    const nlohmann::json request = {
        {"id", next_id_++},
        {"method", "speed"},
        {"params", {{"yaw", 10.0}, {"duration_ms", duration_ms}}},
    };
    const auto moving = gimbal_.speeds_seen();
    motion_starts_.push_back(now_ns());
    if (!write_all(fd_.get(), request.dump() + "\n")) {
        throw std::runtime_error("stop probe: cannot send its speed command");
    }
    std::string line;
    if (!read_line(fd_.get(), pending_, line, 5000)) {
        throw std::runtime_error("stop probe: no reply to its speed command");
    }
    if (line.find("\"result\"") == std::string::npos) {
        throw std::runtime_error("stop probe: speed refused: " + line);
    }
    if (!wait_past([this] { return gimbal_.speeds_seen(); }, moving, kStopTimeoutMs)) {
        throw std::runtime_error("stop probe: its speed never reached the pty");
    }
}

void StopProbe::end_motion(StopCause cause) {
    const auto stops = gimbal_.stops_seen();
    StopSample sample;
    sample.cause = cause;
    sample.before_ns = now_ns();
    if (cause == StopCause::kStopRequest) {
        const auto request = R"({"id":)" + std::to_string(next_id_++) + R"(,"method":"stop"})";
        if (!write_all(fd_.get(), request + "\n")) {
            throw std::runtime_error("stop probe: cannot send stop");
        }
    } else {
        fd_.reset();  // close(): the deadman ends the motion
    }
    sample.cause_ns = now_ns();
    sample.seen = wait_past([this] { return gimbal_.stops_seen(); }, stops, kStopTimeoutMs);
    samples_.push_back(sample);
    if (cause == StopCause::kStopRequest) {
        std::string line;
        if (!read_line(fd_.get(), pending_, line, 5000)) {
            throw std::runtime_error("stop probe: no reply to stop");
        }
    }
}

}  // namespace gport::bench
