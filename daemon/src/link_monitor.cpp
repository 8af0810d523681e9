#include "gport/daemon/core/link_monitor.hpp"

#include <fmt/format.h>

namespace gport::daemon {

LinkMonitor::LinkMonitor(boost::asio::io_context& io, Millis stale_after, OnChange on_change)
    : timer_(io), stale_after_(stale_after), on_change_(std::move(on_change)) {}

void LinkMonitor::device_opened() {
    change(LinkState::kStale, std::string(kWaitingForFirstAttitude));
    arm(std::chrono::steady_clock::now() + stale_after_);
}

void LinkMonitor::device_closed(const std::string& reason) {
    timer_.cancel();
    armed_ = false;
    change(LinkState::kDown, reason);
}

void LinkMonitor::stop() {
    timer_.cancel();
    armed_ = false;
}

void LinkMonitor::attitude_received(SteadyTime now) {
    last_attitude_ = now;
    if (current_.state != LinkState::kUp) {
        change(LinkState::kUp, "attitude arriving");
    }
    if (!armed_) {
        arm(now + stale_after_);
    }
}

void LinkMonitor::arm(SteadyTime deadline) {
    armed_ = true;
    timer_.expires_at(deadline);
    timer_.async_wait([this](boost::system::error_code ec) {
        if (!ec) {
            on_timer();
        }
    });
}

void LinkMonitor::on_timer() {
    armed_ = false;
    if (current_.state == LinkState::kDown) {
        return;
    }
    const auto deadline = last_attitude_ + stale_after_;
    if (current_.state == LinkState::kUp && deadline > std::chrono::steady_clock::now()) {
        arm(deadline);
        return;
    }
    if (current_.state == LinkState::kUp) {
        change(LinkState::kStale, fmt::format("no attitude for {} ms", stale_after_.count()));
    }
}

void LinkMonitor::change(LinkState state, std::string reason) {
    if (state == current_.state && reason == current_.reason) {
        return;
    }
    current_ = LinkEvent{state, std::move(reason)};
    on_change_(current_);
}

}  // namespace gport::daemon
