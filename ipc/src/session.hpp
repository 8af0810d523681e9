// One client connection: reads request lines (bounded), hands them to the
// dispatcher, and writes what its Outbox holds with one write in flight.
// Attitude delivery is rate-limited per client when it asked for it.
#pragma once

#include <array>
#include <boost/asio/local/stream_protocol.hpp>
#include <boost/asio/steady_timer.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gport/ipc/json_rpc.hpp"
#include "gport/ipc/outbox.hpp"

namespace gport::ipc {

class Server;

class Session : public std::enable_shared_from_this<Session> {
  public:
    using Socket = boost::asio::local::stream_protocol::socket;

    Session(Socket socket, daemon::ClientInfo info, Server& server);

    void start();
    // Closes at once; tells the server (which calls client_gone). Idempotent.
    void close();

    const daemon::ClientInfo& info() const { return state_.info; }
    const Subscriptions& subscriptions() const { return state_.subscriptions; }
    bool closed() const { return closed_; }

    void deliver_attitude(const Line& line);
    void deliver_event(const Line& line);  // link or motion: never dropped
    void reply(std::string line);

  private:
    void read();
    void on_read(std::size_t size);
    void handle_line(std::string& line);
    void refuse_long_line();
    void queue_attitude(const Line& line);
    void on_rate_timer();
    void flush();
    void write_rest(std::size_t sent);
    void on_written(const boost::system::error_code& error);
    void overflow();

    Socket socket_;
    Server& server_;
    ClientState state_;
    Outbox outbox_;
    std::array<char, 16384> read_buffer_{};
    std::string partial_;  // the line being received
    std::vector<Line> in_flight_;
    std::vector<boost::asio::const_buffer> buffers_;
    bool writing_ = false;
    bool closing_ = false;  // no more reading; close once the outbox is written
    bool closed_ = false;

    // Attitude rate limit (only when the client asked for max_rate_hz): the
    // newest sample that arrived too soon waits here for the timer.
    std::optional<boost::asio::steady_timer> rate_timer_;
    bool timer_armed_ = false;
    Line pending_attitude_;
    std::chrono::steady_clock::time_point last_attitude_{};
};

}  // namespace gport::ipc
