// Settings requests to the gimbal, one at a time on the wire. A get is
// 0x13 -> 0x14. A set is read-modify-write: 0x13 -> 0x14, change only the
// asked fields (reserved bytes stay exactly as the gimbal reported them),
// 0x15 -> 0x16, then 0x13 -> 0x14 again to report what the gimbal now holds.
// Each step waits the configured timeout and is retried the configured
// number of times; a gimbal that never answers gives kNoAnswer.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <deque>
#include <functional>
#include <optional>

#include "gport/config/config.hpp"
#include "gport/daemon/api.hpp"
#include "gport/protocol/messages.hpp"

namespace gport::daemon {

class SettingsExchange {
  public:
    using Send = std::function<bool(const protocol::Frame&)>;
    using Done = std::function<void(Outcome<protocol::SettingsBlock>)>;

    SettingsExchange(boost::asio::io_context& io, const config::RequestConfig& config, Send send);

    void get(Done done);
    void set(SettingsChange change, Done done);
    // Offer a received 0x14 or 0x16; other messages are ignored.
    void on_report(const protocol::SettingsBlock& block);
    void on_ack();
    // Fails every queued and running request (the daemon is stopping).
    void abort_all(const CommandError& error);

    std::uint64_t timeouts() const { return timeouts_; }

  private:
    enum class Step { kRead, kWrite, kReadBack };
    struct Job {
        std::optional<SettingsChange> change;  // empty: a get
        Done done;
        Step step = Step::kRead;
        unsigned attempt = 0;
        protocol::SettingsBlock block;
    };

    void begin_next();
    void send_step();
    void on_timeout();
    void advance(const protocol::SettingsBlock* report);
    void finish(Outcome<protocol::SettingsBlock> result);

    boost::asio::steady_timer timer_;
    config::RequestConfig config_;
    Send send_;
    std::deque<Job> jobs_;  // front is on the wire
    bool running_ = false;
    std::uint64_t timeouts_ = 0;
};

}  // namespace gport::daemon
