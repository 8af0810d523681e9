// Link health: down while the device is closed, stale while it is open but
// no attitude arrived for the configured time, up while attitude arrives.
// The stale timer is re-armed lazily (from the last arrival when it fires),
// so 500 frames/s cost no timer operations.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <functional>
#include <string>
#include <string_view>

#include "gport/daemon/events.hpp"

namespace gport::daemon {

class LinkMonitor {
  public:
    // The reason of the stale state between the device opening and its first
    // attitude: expected at every start, so logged at debug, not as a problem.
    static constexpr std::string_view kWaitingForFirstAttitude =
        "device open, waiting for the first attitude";

    using OnChange = std::function<void(const LinkEvent&)>;

    LinkMonitor(boost::asio::io_context& io, Millis stale_after, OnChange on_change);

    void device_opened();
    void device_closed(const std::string& reason);
    void attitude_received(SteadyTime now);
    void stop();

    LinkState state() const { return current_.state; }
    const std::string& reason() const { return current_.reason; }

  private:
    void arm(SteadyTime deadline);
    void on_timer();
    void change(LinkState state, std::string reason);

    boost::asio::steady_timer timer_;
    Millis stale_after_;
    OnChange on_change_;
    LinkEvent current_{LinkState::kDown, "device not opened yet"};
    SteadyTime last_attitude_{};
    bool armed_ = false;
};

}  // namespace gport::daemon
