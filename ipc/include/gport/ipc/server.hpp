// The Unix socket server of the client API: accepts clients, runs one
// Session per connection, and fans the core's events out to subscribers.
// It is the core's CoreObserver; the rest of the daemon never sees a socket.
//
// Single-threaded: every call, and every handler, runs on the io_context's
// thread. The one other thread, started with the attitude channel, only
// makes the channel's wakes (ipc/src/channel_waker.hpp) and never calls
// back.
//
//   ipc::Server server(io, core, config.socket, log, activated_fd);
//   server.start();   // throws std::runtime_error with a clear message
//   ...               // on SIGTERM: core.shutdown([&] { server.close(); });
//   io.run();
//
// The core shuts down first (its motions end as `shutdown`, the last stop is
// written and the device closed), and the sessions close in its completion:
// closing them first would end their motions as `owner_gone` instead.
#pragma once

#include <spdlog/logger.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/local/stream_protocol.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <variant>
#include <vector>

#include "gport/base/repeat_limiter.hpp"
#include "gport/capture/capture_log.hpp"
#include "gport/config/config.hpp"
#include "gport/daemon/api.hpp"
#include "gport/ipc/json_rpc.hpp"
#include "gport/ipc/session_host.hpp"

namespace gport::ipc {

class Dispatcher;
class Session;
struct Subscriptions;
namespace detail {
class AttitudeChannel;
}

// What start() throws when the socket's path is not this user's to create or
// replace (EACCES, EPERM): e.g. /run/gportd.sock for a user that is not
// root. The caller can suggest a socket the user may create.
class SocketAccessError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

class Server final : public daemon::CoreObserver, private SessionHost, private ChannelHost {
  public:
    // `listen_fd`: an already listening socket (systemd socket activation);
    // when given, the path, mode and group of `config` are left to the socket
    // unit and the file is neither created nor removed.
    Server(boost::asio::io_context& io, daemon::Api& api, config::SocketConfig config,
           std::shared_ptr<spdlog::logger> log, std::optional<int> listen_fd = std::nullopt);
    ~Server() override;
    Server(const Server&) = delete;
    Server& operator=(const Server&) = delete;

    // Binds (removing a stale socket file, refusing when another daemon
    // answers on the path or the path is not a socket), applies mode and
    // group, registers as the core's observer and starts accepting.
    // Throws std::runtime_error naming the path and the cause.
    void start();

    // Closes the attitude channel (its readers see it closed and wake),
    // stops accepting, closes every session (client_gone for each), detaches
    // from the core and removes the socket file it created. Idempotent; once
    // the pending handlers finish, io.run() returns.
    void close();

    std::size_t clients() const;
    // The configuration file gportd loaded (status's `config_file`), or none.
    void set_config_file(std::optional<std::string> path) { config_file_ = std::move(path); }
    // The capture log (app/ restores it and gives it its writer before start()).
    capture::CaptureLog& captures();
    std::uint64_t dropped_notifications() const { return dropped_total_; }
    // socket.max_clients, or fewer when RLIMIT_NOFILE could not be raised to fit.
    std::size_t max_clients() const { return max_clients_; }
    // Bytes queued for all clients together (outboxes and writes in flight).
    std::size_t queued_bytes() const { return queued_bytes_; }
    // Connected clients that opened the shared-memory attitude channel.
    std::size_t attitude_channel_clients() const;
    // Channels or descriptors that could not be made or sent, since start.
    std::uint64_t attitude_channel_failures() const { return channel_failures_; }
    // The waker thread has made every wake asked for so far (tests, benchmarks).
    bool attitude_wakes_done() const;

    // The memory budget across all sessions (SessionHost::account).
    static constexpr std::size_t kQueuedBudget = 8 * 1024 * 1024;

    // CoreObserver: build each notification once, only when someone listens;
    // every attitude sample also goes into the attitude channel once it exists.
    void on_attitude(const daemon::AttitudeSample& sample) override;
    void on_link(const daemon::LinkEvent& event) override;
    void on_motion(const daemon::MotionEvent& event) override;

  private:
    // SessionHost: what each Session may ask of the server.
    Dispatcher& dispatcher() override { return *dispatcher_; }
    const config::SocketConfig& config() const override { return config_; }
    spdlog::logger& log() override { return *log_; }
    void note_dropped(std::size_t count) override { dropped_total_ += count; }
    void session_closed(const Session& session) override;
    void client_hung_up(const Session& session) override;
    void account(std::size_t before, std::size_t after) override;
    bool over_budget() const override { return queued_bytes_ > kQueuedBudget; }
    bool holds_control_or_motion(const daemon::ClientInfo& client) const override;
    std::array<int, 2> channel_descriptors(const daemon::ClientInfo& client) const override;
    void channel_delivered(const daemon::ClientInfo& client, int error) override;

    // ChannelHost: the attitude_channel method.
    std::variant<ChannelInfo, std::string> open_attitude_channel(ClientState& client,
                                                                 bool deliver) override;

    void accept();
    void on_accept_error(const boost::system::error_code& error);
    void on_accept(boost::asio::local::stream_protocol::socket socket);
    std::optional<std::string> admission(const daemon::ClientInfo& client, bool& asked_core);
    void reject(boost::asio::local::stream_protocol::socket socket, const std::string& why);
    void fit_descriptor_limit();
    void channel_failed(const daemon::ClientInfo& client, const std::string& why);
    void trim_memory();
    template <typename F>
    void for_each_session(F&& visit);
    template <typename Build>
    void publish_event(bool Subscriptions::*topic, Build build);

    boost::asio::io_context& io_;
    daemon::Api& api_;
    config::SocketConfig config_;
    std::shared_ptr<spdlog::logger> log_;
    std::optional<int> listen_fd_;
    boost::asio::local::stream_protocol::acceptor acceptor_;
    std::unique_ptr<Dispatcher> dispatcher_;
    std::unique_ptr<detail::AttitudeChannel> channel_;
    // Exhaustion of descriptors or memory for the channel: counted, and
    // logged once, then as a summary at most once a minute.
    std::uint64_t channel_failures_ = 0;
    base::RepeatLimiter channel_failure_log_{std::chrono::minutes(1)};
    std::unordered_map<std::uint64_t, std::shared_ptr<Session>> sessions_;
    // Sessions that closed while the map was being walked; erased afterwards.
    std::vector<std::uint64_t> closed_ids_;
    int walking_ = 0;
    std::uint64_t next_id_ = 1;
    std::size_t max_clients_;
    std::size_t queued_bytes_ = 0;
    std::size_t queued_peak_ = 0;  // highest queued_bytes_ since the last trim
    std::chrono::steady_clock::time_point last_trim_{};
    std::size_t closed_since_trim_ = 0;
    boost::asio::steady_timer trim_timer_;  // a trim that was due too soon after the last
    bool trim_armed_ = false;
    // Clients whose supplementary groups could not be read (SO_PEERGROUPS):
    // judged by uid and primary gid; logged once, then at most once a minute.
    base::RepeatLimiter peer_groups_log_{std::chrono::minutes(1)};
    // Refused clients are summarised in the log, not one line each.
    std::uint64_t refused_ = 0;
    std::chrono::steady_clock::time_point refused_logged_{};
    // Out of descriptors: accepting pauses; failures are summarised in the log.
    boost::asio::steady_timer accept_pause_;
    std::uint64_t accept_failures_ = 0;
    std::chrono::steady_clock::time_point accept_logged_{};
    std::uint64_t dropped_total_ = 0;
    std::optional<std::string> config_file_;
    bool created_file_ = false;
    bool started_ = false;
    bool closed_ = false;
};

}  // namespace gport::ipc
