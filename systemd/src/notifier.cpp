#include "gport/systemd/notifier.hpp"

#include <spdlog/spdlog.h>
#include <systemd/sd-daemon.h>

#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>

namespace gport::systemd {

Notifier::Notifier(std::shared_ptr<spdlog::logger> log) : log_(std::move(log)) {}

bool Notifier::enabled() const {
    const char* socket = std::getenv("NOTIFY_SOCKET");
    return socket != nullptr && *socket != '\0';
}

bool Notifier::ready() {
    return send("READY=1");
}

bool Notifier::status(std::string_view text) {
    if (last_status_ && *last_status_ == text) {
        return false;
    }
    std::string message = "STATUS=";
    message += text;
    const bool sent = send(message);
    if (sent) {
        last_status_ = std::string(text);
    }
    return sent;
}

bool Notifier::reloading() {
    timespec now{};
    ::clock_gettime(CLOCK_MONOTONIC, &now);
    const auto usec = static_cast<unsigned long long>(now.tv_sec) * 1000000ULL +
                      static_cast<unsigned long long>(now.tv_nsec) / 1000ULL;
    return send("RELOADING=1\nMONOTONIC_USEC=" + std::to_string(usec));
}

bool Notifier::stopping() {
    return send("STOPPING=1");
}

bool Notifier::watchdog() {
    return send("WATCHDOG=1");
}

std::optional<std::chrono::microseconds> Notifier::watchdog_timeout() {
    uint64_t usec = 0;
    if (sd_watchdog_enabled(0, &usec) <= 0 || usec == 0) {
        return std::nullopt;
    }
    return std::chrono::microseconds(usec);
}

bool Notifier::send(std::string_view message) {
    if (!enabled()) {
        return false;
    }
    const std::string text(message);
    const int result = sd_notify(0, text.c_str());
    auto& log = log_ ? *log_ : *spdlog::default_logger();
    // Log the first failure and the recovery only: the watchdog would
    // otherwise repeat the same warning every few seconds.
    if (result <= 0) {
        if (!failing_) {
            log.warn("sd_notify({}) failed: {}; NOTIFY_SOCKET={}", text,
                     result < 0 ? std::strerror(-result) : "not sent",
                     std::getenv("NOTIFY_SOCKET"));
        }
        failing_ = true;
        return false;
    }
    if (failing_) {
        log.info("sd_notify works again");
        failing_ = false;
    }
    return true;
}

}  // namespace gport::systemd
