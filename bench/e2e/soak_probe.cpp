#include "soak_probe.hpp"

#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>

#include "posix.hpp"

namespace gport::bench {

void SubscriberProbe::start() {
    thread_ = std::thread([this] { run(); });
}

void SubscriberProbe::stop() {
    stop_ = true;
    if (thread_.joinable()) {
        thread_.join();
    }
}

ProbeFigures SubscriberProbe::figures() const {
    std::lock_guard lock(mutex_);
    return figures_;
}

void SubscriberProbe::run() {
    auto fd = connect_unix_retry(socket_, 10000);
    if (!fd) {
        return;
    }
    {
        std::lock_guard lock(mutex_);
        figures_.connected = true;
    }
    write_all(fd->get(), R"({"id":1,"method":"subscribe","params":{"topics":["attitude","link"]}})"
                         "\n");
    std::string pending;
    std::string line;
    while (!stop_) {
        if (read_line(fd->get(), pending, line, 100)) {
            on_line(line);
            continue;
        }
        char probe = 0;  // a timeout, or did the daemon close the connection?
        if (::recv(fd->get(), &probe, 1, MSG_PEEK | MSG_DONTWAIT) == 0) {
            std::lock_guard lock(mutex_);
            figures_.closed_by_daemon = true;
            return;
        }
    }
}

void SubscriberProbe::on_line(const std::string& line) {
    const auto t = now_ns();
    if (line.find(R"("method":"link")") != std::string::npos) {
        link_changed_ = true;
        return;
    }
    if (line.find(R"("method":"attitude")") == std::string::npos) {
        return;
    }
    std::lock_guard lock(mutex_);
    ++figures_.attitude_lines;
    if (last_attitude_ns_ != 0) {
        const auto gap_ms = static_cast<double>(t - last_attitude_ns_) / 1e6;
        if (link_changed_) {
            ++figures_.excused_gaps;
        } else {
            figures_.max_gap_ms = std::max(figures_.max_gap_ms, gap_ms);
            figures_.gaps_over_limit += gap_ms > limit_ms_ ? 1 : 0;
        }
    }
    last_attitude_ns_ = t;
    link_changed_ = false;
}

}  // namespace gport::bench
