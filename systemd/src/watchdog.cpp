#include "gport/systemd/watchdog.hpp"

#include <algorithm>
#include <boost/system/error_code.hpp>

namespace gport::systemd {

WatchdogDriver::WatchdogDriver(boost::asio::io_context& io, Notifier& notifier)
    : timer_(io), notifier_(notifier) {}

std::optional<std::chrono::microseconds> WatchdogDriver::start() {
    const auto timeout = Notifier::watchdog_timeout();
    if (!timeout) {
        return std::nullopt;
    }
    // Half the timeout, as sd_watchdog_enabled(3) recommends: one late ping
    // on a busy machine must not get the daemon killed.
    interval_ = std::max(*timeout / 2, std::chrono::microseconds(1));
    notifier_.watchdog();
    timer_.expires_after(*interval_);
    schedule();
    return interval_;
}

void WatchdogDriver::stop() {
    interval_.reset();
    timer_.cancel();
}

void WatchdogDriver::schedule() {
    timer_.async_wait([this](const boost::system::error_code& error) {
        if (error || !interval_) {
            return;  // cancelled by stop() or the driver's destruction
        }
        notifier_.watchdog();
        // From the previous deadline, not from now, so pings do not drift;
        // but after a stall, no burst of catch-up pings.
        const auto now = boost::asio::steady_timer::clock_type::now();
        const auto next = timer_.expiry() + *interval_;
        timer_.expires_at(next > now ? next : now + *interval_);
        schedule();
    });
}

}  // namespace gport::systemd
