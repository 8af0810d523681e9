// Settings requests to the gimbal, one at a time on the wire. A get is
// 0x13 -> 0x14. A set is read-modify-write: 0x13 -> 0x14, change only the
// asked fields (reserved bytes stay exactly as the gimbal reported them),
// 0x15 -> 0x16, then 0x13 -> 0x14 again to report what the gimbal now holds.
// Each step waits the configured timeout and is retried the configured
// number of times; a gimbal that never answers gives kNoAnswer.
// Requests are capped per client and in total (a gimbal that never answers
// must not let them pile up), and a closed client's requests are dropped.
// Results are always delivered from the loop (a timer or a received frame),
// never from inside get()/set().
#pragma once

#include <spdlog/logger.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "gport/config/config.hpp"
#include "gport/daemon/api.hpp"
#include "gport/protocol/messages.hpp"

namespace gport::daemon {

class SettingsExchange {
  public:
    // Queues a frame for the device; the error when it could not be queued.
    using Send = std::function<std::optional<CommandError>(const protocol::Frame&)>;
    // Called once with the request's result, from the loop.
    using Reply = std::function<void(Outcome<protocol::SettingsBlock>)>;

    static constexpr std::size_t kMaxPerClient = 4;
    static constexpr std::size_t kMaxTotal = 64;

    // A set that went through is logged at info level with what it changed.
    SettingsExchange(boost::asio::io_context& io, const config::RequestConfig& config, Send send,
                     std::shared_ptr<spdlog::logger> log);

    // kTooManyRequests when the client, or everyone together, has too many requests
    // waiting; check before get()/set().
    std::optional<CommandError> admit(std::uint64_t client) const;
    // A client's request as the API takes it: `refused` (the core's
    // admission) or admit()'s refusal is posted to done; otherwise a get (no
    // change) or a set, whose block done receives as Settings.
    void request(std::uint64_t client, std::optional<CommandError> refused,
                 std::optional<SettingsChange> change, Api::SettingsCallback done);
    void get(std::uint64_t client, Reply reply);
    void set(std::uint64_t client, SettingsChange change, Reply reply);
    // The client's connection closed: its waiting requests are dropped and
    // the running one, if its, finishes without calling back.
    void forget(std::uint64_t client);
    // Offer a received 0x14 or 0x16; other messages are ignored.
    void on_report(const protocol::SettingsBlock& block);
    void on_ack();
    // Fails every queued and running request (the daemon is stopping).
    void abort_all(const CommandError& error);

    std::uint64_t timeouts() const { return timeouts_; }

  private:
    enum class Step { kRead, kWrite, kReadBack };
    struct Job {
        std::uint64_t client = 0;
        std::optional<SettingsChange> change;  // empty: a get
        Reply reply;                           // empty once the client is gone
        Step step = Step::kRead;
        unsigned attempt = 0;
        protocol::SettingsBlock block;
        std::optional<protocol::SettingsBlock> before;  // a set: the block first read
        std::optional<CommandError> refused;  // the frame was not queued: fail at the timer
    };

    void enqueue(Job job);
    void begin_next();
    void send_step();
    void on_timeout();
    void advance(const protocol::SettingsBlock* report);
    void finish(Outcome<protocol::SettingsBlock> result);

    boost::asio::steady_timer timer_;
    config::RequestConfig config_;
    Send send_;
    std::shared_ptr<spdlog::logger> log_;
    std::deque<Job> jobs_;  // front is on the wire
    bool running_ = false;
    std::uint64_t timeouts_ = 0;
};

}  // namespace gport::daemon
