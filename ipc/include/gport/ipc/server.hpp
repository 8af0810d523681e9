// The Unix socket server of the client API: accepts clients, runs one
// Session per connection, and fans the core's events out to subscribers.
// It is the core's CoreObserver; the rest of the daemon never sees a socket.
//
// Single-threaded: every call, and every handler, runs on the io_context's
// thread.
//
//   ipc::Server server(io, core, config.socket, log, activated_fd);
//   server.start();   // throws std::runtime_error with a clear message
//   ...               // signal handler: server.close(); core.shutdown(...)
//   io.run();
#pragma once

#include <spdlog/logger.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/local/stream_protocol.hpp>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "gport/config/config.hpp"
#include "gport/daemon/api.hpp"
#include "gport/ipc/json_rpc.hpp"

namespace gport::ipc {

class Session;

class Server final : public daemon::CoreObserver {
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

    // Stops accepting, closes every session (client_gone for each), detaches
    // from the core and removes the socket file it created. Idempotent; once
    // the pending handlers finish, io.run() returns.
    void close();

    std::size_t clients() const;
    std::uint64_t dropped_notifications() const { return dropped_total_; }

    // CoreObserver: build each notification once, only when someone listens.
    void on_attitude(const daemon::AttitudeSample& sample) override;
    void on_link(const daemon::LinkEvent& event) override;
    void on_motion(const daemon::MotionEvent& event) override;

    // ---- for sessions ----
    Dispatcher& dispatcher() { return dispatcher_; }
    const config::SocketConfig& config() const { return config_; }
    spdlog::logger& log() { return *log_; }
    void note_dropped(std::size_t count) { dropped_total_ += count; }
    void session_closed(const Session& session);

  private:
    void accept();
    void on_accept(boost::asio::local::stream_protocol::socket socket);
    void reject(boost::asio::local::stream_protocol::socket socket);
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
    Dispatcher dispatcher_;
    std::unordered_map<std::uint64_t, std::shared_ptr<Session>> sessions_;
    // Sessions that closed while the map was being walked; erased afterwards.
    std::vector<std::uint64_t> closed_ids_;
    int walking_ = 0;
    std::uint64_t next_id_ = 1;
    std::uint64_t dropped_total_ = 0;
    bool created_file_ = false;
    bool started_ = false;
    bool closed_ = false;
};

}  // namespace gport::ipc
