// One client connection: reads request lines (bounded), hands them to the
// dispatcher, and writes what its Outbox holds with one write in flight.
// Attitude delivery is rate-limited per client when it asked for it.
//
// Fairness and memory (docs/api.md, "Limits"):
// - At most kLinesPerTurn request lines are handled per loop turn; the rest
//   wait in `input_` and the continuation is posted, so serial reads and
//   timers run in between.
// - Back-pressure: while the replies queued for this client exceed
//   kPauseBytes (or the server is over its memory budget and this client has
//   anything queued), no further request is handled and nothing is read;
//   handling resumes when the client has read its replies.
// - Over the request rate, requests get -32005; once its tokens run out the
//   client is not read until a batch's worth of requests is allowed again,
//   so a flood costs neither CPU nor memory.
// - Half-close: at EOF the deadman runs at once (SessionHost::client_hung_up) but
//   the connection stays open until every outstanding reply is written.
//
// What it waits for and whether it is open is one SessionState (life, input,
// output; gport/ipc/session_state.hpp), changed only through advance().
#pragma once

#include <array>
#include <boost/asio/local/stream_protocol.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gport/ipc/attitude_pacer.hpp"
#include "gport/ipc/json_rpc.hpp"
#include "gport/ipc/outbox.hpp"
#include "gport/ipc/session_host.hpp"
#include "gport/ipc/session_state.hpp"

namespace gport::ipc {

class Session : public std::enable_shared_from_this<Session> {
  public:
    using Socket = boost::asio::local::stream_protocol::socket;
    using Clock = std::chrono::steady_clock;

    // Request lines handled per loop turn before yielding to other handlers.
    static constexpr std::size_t kLinesPerTurn = 8;
    // Queued reply bytes above which this client's requests wait.
    static constexpr std::size_t kPauseBytes = 64 * 1024;

    Session(Socket socket, daemon::ClientInfo info, SessionHost& host);

    void start();
    // Closes at once; tells the host, which calls the core afterwards
    // (never from inside whatever is running now). Idempotent.
    void close();

    const daemon::ClientInfo& info() const { return state_.info; }
    const Subscriptions& subscriptions() const { return state_.subscriptions; }
    bool opened_attitude_channel() const { return state_.attitude_channel; }
    bool closed() const { return lifecycle_.life == Life::kClosed; }
    // The client sent EOF and the deadman has already run for it.
    bool hung_up() const { return lifecycle_.input == Input::kHungUp; }

    void deliver_attitude(const AttitudeLine& line);
    void deliver_event(const Line& line);  // link or motion: never dropped
    // The request line being handled opened the attitude channel: its reply
    // line (a batch's one line too) carries `count` descriptors, sent with
    // its first byte (session_descriptors.cpp). The server calls this from
    // ChannelHost::open_attitude_channel, inside handle_line.
    void attach_descriptors(std::size_t count);

  private:
    // Queues a reply line with the descriptors attached to its request.
    void reply(std::string line, std::size_t descriptors = 0);
    // The one way the state changes: false (and logged) when the table
    // refuses the event, which is a bug; the state is left as it was.
    bool advance(SessionEvent event);
    bool open() const { return lifecycle_.life == Life::kOpen; }

    // ---- input (session.cpp) ----
    void read();
    void on_read(const boost::system::error_code& error, std::size_t size);
    void post_input(SessionEvent event);
    void process_input();
    void handle_line(std::string_view line);
    void request_done();
    void refuse_long_line();
    void hang_up();
    bool backlogged() const;
    bool throttle();
    void arm_idle_timer(Clock::duration after);
    void on_idle_timer();
    bool busy() const;
    void close_after_reply(int code, const std::string& message);

    // ---- output (session_output.cpp) ----
    void queue_attitude(const AttitudeLine& line);
    void on_rate_timer();
    void flush();
    void write_queued();
    void write_rest(std::size_t sent);
    void on_written(const boost::system::error_code& error);
    void drained();
    void finish_if_done();
    void overflow(std::size_t refused_bytes);
    void sync_budget();

    // ---- descriptors (session_descriptors.cpp) ----
    bool send_with_descriptors();
    void wait_writable();

    Socket socket_;
    SessionHost& host_;
    ClientState state_;
    Outbox outbox_;
    std::array<char, 16384> read_buffer_{};
    std::string input_;            // received, not yet handled; lines end in '\n'
    std::size_t consumed_ = 0;     // bytes of input_ already handled
    std::size_t outstanding_ = 0;  // requests whose reply has not been queued
    // The descriptors attach_descriptors gave the request line being
    // handled; null between lines.
    std::shared_ptr<std::size_t> attached_;
    SessionState lifecycle_;

    std::vector<Line> in_flight_;
    std::size_t in_flight_bytes_ = 0;
    std::size_t accounted_ = 0;  // bytes reported to the server's budget
    std::vector<boost::asio::const_buffer> buffers_;

    boost::asio::steady_timer idle_timer_;
    boost::asio::steady_timer throttle_timer_;
    Clock::time_point last_request_;

    // Attitude rate limit (only when the client asked for max_rate_hz): the
    // pacer decides, the timer wakes it for the newest sample held.
    AttitudePacer pacer_;
    std::optional<boost::asio::steady_timer> rate_timer_;
};

}  // namespace gport::ipc
