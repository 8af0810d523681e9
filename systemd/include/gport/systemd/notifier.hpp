// sd_notify(3) for gportd: READY=1, RELOADING=1, STATUS=, WATCHDOG=1 and
// STOPPING=1.
//
// Every call is a no-op when NOTIFY_SOCKET is unset (the daemon runs without
// systemd, or under a Type= that does not listen), so the daemon calls these
// unconditionally. The watchdog pings themselves are driven from the event
// loop by WatchdogDriver (watchdog.hpp).
#pragma once

#include <spdlog/logger.h>

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

namespace gport::systemd {

class Notifier {
  public:
    // Messages that fail to reach systemd are logged to `log` (the spdlog
    // default logger when null): the first failure, and the recovery after it.
    explicit Notifier(std::shared_ptr<spdlog::logger> log = nullptr);

    // True when NOTIFY_SOCKET is set, i.e. systemd listens for our messages.
    [[nodiscard]] bool enabled() const;

    // READY=1: the client socket listens; systemd starts the units ordered
    // after us. Send once, after the listening socket exists.
    bool ready();

    // STATUS=<text>, shown by `systemctl status`. Sent only when the text
    // differs from the last one sent, so callers may call on every event.
    bool status(std::string_view text);

    // RELOADING=1 (with MONOTONIC_USEC=, which newer systemd wants): a
    // configuration reload began; send ready() when it is over, whatever its
    // outcome, so `systemctl reload` returns.
    bool reloading();

    // STOPPING=1: shutdown began (send before the last log lines and exit).
    bool stopping();

    // WATCHDOG=1: the event loop is alive.
    bool watchdog();

    // The watchdog period WATCHDOG_USEC asks for, when systemd enabled the
    // watchdog for this process (sd_watchdog_enabled: WATCHDOG_USEC set and
    // WATCHDOG_PID, if set, is our pid); std::nullopt otherwise.
    [[nodiscard]] static std::optional<std::chrono::microseconds> watchdog_timeout();

    // Each call returns true when the message was sent, false when systemd
    // does not listen or the send failed.

  private:
    bool send(std::string_view message);

    std::shared_ptr<spdlog::logger> log_;
    std::optional<std::string> last_status_;
    bool failing_ = false;
};

}  // namespace gport::systemd
