// One client connection, in the shape of Asio's C++20 chat server: a reader
// and a writer coroutine (and an idle watch). Replies and notifications are
// written at once while the socket has room (docs/performance.md, "Send
// directly when the socket has room"); the writer writes only what did not
// fit, one write in flight. Attitude is rate-limited when the client asked.
//
// Fairness and memory (docs/api.md, "Limits"):
// - At most kLinesPerTurn request lines per loop turn, then the reader
//   co_awaits a post, so serial reads and timers run in between.
// - Back-pressure: while more than kPauseBytes of replies wait (or the
//   server is over its memory budget and any do), the reader neither handles
//   nor reads, until the client has read its replies.
// - Over the request rate, requests get -32005; once its tokens run out the
//   reader sleeps until a batch's worth is allowed: a flood costs nothing.
// - Half-close: at EOF the deadman runs at once (SessionHost::client_hung_up);
//   the connection stays open until every outstanding reply is written.
// Life: open -> closing (no more requests; closes once every reply owed is
// written) -> closed, when close() cancels every wait and the coroutines end.
#pragma once

// clang-format off
#include <utility>  // before it: Boost 1.74's awaitable.hpp uses std::exchange
#include <boost/asio/awaitable.hpp>
// clang-format on

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
    bool closed() const { return life_ == Life::kClosed; }
    // The client sent EOF and the deadman has already run for it.
    bool hung_up() const { return hung_up_; }

    void deliver_attitude(const AttitudeLine& line);
    void deliver_event(const Line& line);  // link or motion: never dropped
    // The request line being handled opened the attitude channel: its reply
    // line (a batch's one line too) carries `count` descriptors, sent with
    // its first byte. The server calls this from
    // ChannelHost::open_attitude_channel, inside handle_line.
    void attach_descriptors(std::size_t count);

  private:
    enum class Life { kOpen, kClosing, kClosed };
    template <typename T>
    using Awaitable = boost::asio::awaitable<T>;

    bool open() const { return life_ == Life::kOpen; }
    void spawn(Awaitable<void> (Session::*body)());

    // ---- input ----
    Awaitable<void> reader();
    Awaitable<void> idle_watch();
    void handle_line(std::string_view line);
    void hang_up(std::string_view rest);
    void refuse_long_line();
    bool backlogged() const;
    std::optional<Clock::duration> throttle() const;
    bool busy() const;
    void close_after_reply(int code, const std::string& message);

    // ---- output ----
    void reply(std::string line, std::size_t descriptors = 0);
    void queue_attitude(const AttitudeLine& line);
    Awaitable<void> pace();
    void queue(const Line& line, std::size_t descriptors);
    void flush();
    void write_queued();
    bool send_with_descriptors();
    void write_later(std::size_t sent);
    Awaitable<void> writer();
    void finish_if_done();
    void sync_budget();

    Socket socket_;
    SessionHost& host_;
    ClientState state_;
    Outbox outbox_;
    Life life_ = Life::kOpen;
    bool hung_up_ = false;
    std::array<char, 16384> read_buffer_{};
    std::string input_;            // received, not yet handled; lines end in '\n'
    std::size_t outstanding_ = 0;  // requests whose reply has not been queued
    // The descriptors attach_descriptors gave the request line being
    // handled; null between lines.
    std::shared_ptr<std::size_t> attached_;

    // The one write in flight: its lines (kept alive until written), the
    // buffers of what is left of them, their bytes (counted in the budget).
    // `pending` while the writer coroutine owns it: the rest of the batch,
    // or, when `wait_writable`, room in the socket for a reply with
    // descriptors.
    struct Write {
        bool pending = false;
        bool wait_writable = false;
        std::vector<Line> lines;
        std::vector<boost::asio::const_buffer> buffers;
        std::size_t bytes = 0;

        // The buffers and bytes of `lines`, all of them unsent.
        void cover();
        // Skips the first `sent` bytes of the buffers (write_some sent them).
        void skip(std::size_t sent);
        void clear();
    };
    Write write_;
    bool paused_ = false;        // the reader waits on unpause_
    std::size_t accounted_ = 0;  // bytes reported to the server's budget

    // Signals, as in Asio's chat server: timers that never expire, cancelled
    // to wake the coroutine waiting on them.
    boost::asio::steady_timer wake_writer_;
    boost::asio::steady_timer unpause_;
    boost::asio::steady_timer idle_timer_;
    boost::asio::steady_timer throttle_timer_;
    Clock::time_point last_request_;

    // Attitude rate limit (only when the client asked for max_rate_hz): the
    // pacer decides; pace() sleeps on the timer until the newest sample held
    // is due (timer and coroutine made at the first sample held).
    AttitudePacer pacer_;
    std::optional<boost::asio::steady_timer> rate_timer_;
};

}  // namespace gport::ipc
