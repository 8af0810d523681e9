// Drives WATCHDOG=1 from the event loop, at half of WATCHDOG_USEC.
//
// The pings are sent by a timer on the daemon's own io_context, never by a
// helper thread: if the loop is stuck, the pings stop and systemd kills and
// restarts the daemon. Nothing is scheduled when the watchdog is disabled.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <optional>

#include "gport/systemd/notifier.hpp"

namespace gport::systemd {

class WatchdogDriver {
  public:
    // `notifier` must outlive the driver.
    WatchdogDriver(boost::asio::io_context& io, Notifier& notifier);

    WatchdogDriver(const WatchdogDriver&) = delete;
    WatchdogDriver& operator=(const WatchdogDriver&) = delete;

    // Reads WATCHDOG_USEC; when the watchdog is enabled, sends WATCHDOG=1 at
    // once and then every WATCHDOG_USEC/2 and returns the interval. Returns
    // std::nullopt (and schedules nothing) when it is disabled.
    std::optional<std::chrono::microseconds> start();

    // Cancels the timer so io_context::run() can return. Idempotent.
    void stop();

    // The ping interval while running.
    [[nodiscard]] std::optional<std::chrono::microseconds> interval() const { return interval_; }

  private:
    void schedule();

    boost::asio::steady_timer timer_;
    Notifier& notifier_;
    std::optional<std::chrono::microseconds> interval_;
};

}  // namespace gport::systemd
