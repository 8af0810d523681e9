// A session: the reader, writer and idle-watch coroutines, the queueing of
// replies and notifications, the attitude rate limit, and the reply that
// carries the attitude channel's descriptors (SCM_RIGHTS on its first byte,
// after every line queued before it; docs/api.md, "Shared-memory attitude
// channel").
#include "session.hpp"

#include <fmt/format.h>
#include <spdlog/logger.h>
#include <sys/socket.h>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <boost/asio/write.hpp>
#include <cerrno>
#include <cstring>
#include <exception>
#include <functional>
#include <utility>

#include "attitude_channel.hpp"
#include "gport/base/descriptors.hpp"
#include "gport/config/config.hpp"

namespace gport::ipc {
namespace {

namespace asio = boost::asio;
using boost::system::error_code;

// Lines gathered into one write: enough to amortise the syscall, few enough
// that one write stays short.
constexpr std::size_t kLinesPerWrite = 64;

auto with(error_code& error) {
    return asio::redirect_error(asio::use_awaitable, error);
}

bool blank(std::string_view line) {
    return line.find_first_not_of(" \t\r") == std::string_view::npos;
}

// Tracks one request until its reply is queued. The reply sink may be
// copied into the core (settings) or a batch; when the last copy goes
// without having answered (a notification, or a request the core dropped),
// the request is over all the same.
class Pending {
  public:
    explicit Pending(std::function<void()> done) : done_(std::move(done)) {}
    ~Pending() { finish(); }
    Pending(const Pending&) = delete;
    Pending& operator=(const Pending&) = delete;

    void finish() {
        if (auto done = std::exchange(done_, nullptr)) {
            done();
        }
    }

  private:
    std::function<void()> done_;
};

}  // namespace

Session::Session(Socket socket, daemon::ClientInfo info, SessionHost& host)
    : socket_(std::move(socket)),
      host_(host),
      state_{info, {}, 0, RequestRate(static_cast<double>(host.config().max_requests_per_s))},
      outbox_(host.config().queue_limit),
      wake_writer_(socket_.get_executor(), Clock::time_point::max()),
      unpause_(socket_.get_executor(), Clock::time_point::max()),
      idle_timer_(socket_.get_executor()),
      throttle_timer_(socket_.get_executor()),
      last_request_(Clock::now()) {}

void Session::start() {
    // Writes are tried at once (see flush); reads stay asynchronous.
    error_code ignored;
    socket_.non_blocking(true, ignored);
    for (auto body : {&Session::reader, &Session::writer, &Session::idle_watch}) {
        spawn(body);
    }
}

// Each coroutine holds the session alive until it returns.
void Session::spawn(Awaitable<void> (Session::*body)()) {
    asio::co_spawn(
        socket_.get_executor(), [self = shared_from_this(), body] { return (*self.*body)(); },
        [](const std::exception_ptr& thrown) {
            if (thrown) {
                std::rethrow_exception(thrown);
            }
        });
}

void Session::close() {
    if (closed()) {
        return;
    }
    life_ = Life::kClosed;
    error_code ignored;
    socket_.shutdown(Socket::shutdown_both, ignored);
    socket_.close(ignored);
    wake_writer_.cancel();
    unpause_.cancel();
    idle_timer_.cancel();
    throttle_timer_.cancel();
    if (rate_timer_) {
        rate_timer_->cancel();
    }
    pacer_.clear();
    sync_budget();
    host_.session_closed(*this);
}

// ---- input ----------------------------------------------------------------------

// Handles up to kLinesPerTurn complete lines per turn; reads more only when
// no complete line is left and the client's replies are drained.
Session::Awaitable<void> Session::reader() {
    const std::size_t limit = host_.config().line_limit;
    std::size_t consumed = 0;  // bytes of input_ already handled
    std::size_t handled = 0;   // lines this turn
    error_code error;
    while (open()) {
        if (backlogged()) {
            paused_ = true;  // flush() wakes it once everything is written
            co_await unpause_.async_wait(with(error));
            handled = 0;
            continue;
        }
        const auto newline = input_.find('\n', consumed);
        if (newline == std::string::npos) {
            input_.erase(0, std::exchange(consumed, 0));
            if (input_.size() > limit) {
                refuse_long_line();
                co_return;
            }
            const auto size =
                co_await socket_.async_read_some(asio::buffer(read_buffer_), with(error));
            if (!open()) {
                co_return;
            }
            if (error == asio::error::eof) {
                hang_up(input_);
                co_return;
            }
            if (error) {
                close();  // reset: the client cannot read replies either
                co_return;
            }
            input_.append(read_buffer_.data(), size);
            handled = 0;
            continue;
        }
        if (newline - consumed > limit) {
            refuse_long_line();
            co_return;
        }
        if (handled++ == kLinesPerTurn) {
            co_await asio::post(socket_.get_executor(), asio::use_awaitable);
            handled = 0;
            continue;
        }
        if (handled == 1) {
            last_request_ = Clock::now();
        }
        const auto line = std::string_view(input_).substr(consumed, newline - consumed);
        consumed = newline + 1;
        handle_line(line);
        if (const auto wait = throttle()) {
            throttle_timer_.expires_after(*wait);
            co_await throttle_timer_.async_wait(with(error));
            handled = 0;
        }
    }
}

void Session::handle_line(std::string_view line) {
    if (!line.empty() && line.back() == '\r') {
        line.remove_suffix(1);  // tolerate CRLF from terminals
    }
    if (blank(line)) {
        return;
    }
    ++outstanding_;
    auto weak = weak_from_this();
    auto pending = std::make_shared<Pending>([weak] {
        if (auto self = weak.lock()) {
            --self->outstanding_;
            self->finish_if_done();
        }
    });
    // A reply may come later (settings, or a batch waiting for one): it
    // keeps the count attached while this line was handled.
    auto attached = std::make_shared<std::size_t>(0);
    attached_ = attached;
    host_.dispatcher().handle_line(line, state_, [weak, pending, attached](std::string reply) {
        if (auto self = weak.lock()) {
            self->reply(std::move(reply), *attached);
        }
        pending->finish();
    });
    attached_.reset();
}

void Session::attach_descriptors(std::size_t count) {
    if (attached_) {
        *attached_ += count;
    }
}

// Out of request tokens (the client was just refused, or is about to be):
// wait until a whole batch would be allowed, rather than answer the rest of
// a flood with errors at full speed.
std::optional<Session::Clock::duration> Session::throttle() const {
    const auto& rate = state_.rate;
    if (rate.has_token(Clock::now()) || !open()) {
        return std::nullopt;
    }
    const auto wait = rate.wait_for(static_cast<double>(kMaxBatch), Clock::now());
    if (wait <= Clock::duration::zero()) {
        return std::nullopt;
    }
    return wait;
}

bool Session::backlogged() const {
    const std::size_t queued = outbox_.reply_bytes() + write_.bytes;
    return queued > kPauseBytes || (queued > 0 && host_.over_budget());
}

void Session::refuse_long_line() {
    host_.log().warn("client pid {} uid {}: request line longer than {} bytes; closing",
                     state_.info.pid, state_.info.uid, host_.config().line_limit);
    close_after_reply(rpc_error::kInvalidRequest,
                      fmt::format("request line longer than {} bytes; closing the connection",
                                  host_.config().line_limit));
}

// Stops reading, sends one last error, and closes once everything is written.
void Session::close_after_reply(int code, const std::string& message) {
    reply(error_line(code, message));
    if (open()) {  // else the reply overflowed the queue and closed it
        life_ = Life::kClosing;
    }
    input_.clear();
    input_.shrink_to_fit();
    flush();
}

// EOF: a last line without '\n' still counts; the deadman runs now; the
// connection closes once the replies owed are written (finish_if_done).
void Session::hang_up(std::string_view rest) {
    if (rest.size() <= host_.config().line_limit) {
        handle_line(rest);
        if (closed()) {
            return;  // it overflowed: closing already told the server
        }
    }
    life_ = Life::kClosing;
    hung_up_ = true;
    input_.clear();
    input_.shrink_to_fit();
    host_.client_hung_up(*this);
    flush();
}

// Wakes once per timeout, not per request: it looks at the last request.
Session::Awaitable<void> Session::idle_watch() {
    const auto timeout = host_.config().idle_timeout;
    Clock::duration after = timeout;
    for (error_code error; !error && open();) {
        idle_timer_.expires_after(after);
        co_await idle_timer_.async_wait(with(error));
        const auto quiet = Clock::now() - last_request_;
        after = quiet < timeout ? timeout - quiet : timeout;
        if (error || !open() || quiet < timeout || busy()) {
            continue;
        }
        host_.log().info("client {} (pid {} uid {}) idle for {} ms; closing it", state_.info.id,
                         state_.info.pid, state_.info.uid, timeout.count());
        close_after_reply(
            rpc_error::kNoSlot,
            fmt::format("idle for {} ms with no subscription (socket.idle_timeout_ms); closing",
                        timeout.count()));
    }
}

// Quiet is fine for a client that listens (on the socket or through the
// attitude channel), waits for an answer, holds control or owns a motion:
// closing it would stop the gimbal or lose data.
bool Session::busy() const {
    const auto& s = state_.subscriptions;
    return s.attitude || s.link || s.motion || state_.attitude_channel || outstanding_ > 0 ||
           host_.holds_control_or_motion(state_.info);
}

// ---- queueing -------------------------------------------------------------------

void Session::reply(std::string line, std::size_t descriptors) {
    if (!closed()) {
        queue(std::make_shared<const std::string>(std::move(line)), descriptors);
    }
}

void Session::deliver_event(const Line& line) {
    if (open()) {
        queue(line, 0);
    }
}

// A line that does not fit closes the session; only the server is told, the
// core hears of it after the current event.
void Session::queue(const Line& line, std::size_t descriptors) {
    if (outbox_.push(line, descriptors)) {
        flush();
        return;
    }
    host_.log().warn(
        "client pid {} uid {}: a line of {} bytes does not fit its output queue ({} lines, {} "
        "bytes wait unread); disconnecting it",
        state_.info.pid, state_.info.uid, line->size(), outbox_.size(), outbox_.bytes());
    close();
}

void Session::deliver_attitude(const AttitudeLine& line) {
    if (!open()) {
        return;
    }
    const auto& rate = state_.subscriptions.max_rate_hz;
    if (!rate) {
        queue_attitude(line);
        return;
    }
    // max_rate_hz is at least kMinRateHz, so the interval fits a duration.
    const auto interval =
        std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / *rate));
    switch (pacer_.offer(line, Clock::now(), interval)) {
        case AttitudePacer::Decision::kSend:
            queue_attitude(line);
            return;
        case AttitudePacer::Decision::kHold:
            return;
        case AttitudePacer::Decision::kHoldAndWake:
            break;
    }
    if (rate_timer_) {
        rate_timer_->cancel();  // wakes pace() to sleep until wake_at()
        return;
    }
    rate_timer_.emplace(socket_.get_executor());
    spawn(&Session::pace);
}

// The rate limit's wake-ups, from the first sample the pacer held on: sleeps
// until its wake-up and sends the newest sample held, then waits (the timer
// as a signal, as wake_writer_) until deliver_attitude holds another.
Session::Awaitable<void> Session::pace() {
    error_code error;
    while (open()) {
        if (!pacer_.waking()) {
            rate_timer_->expires_at(Clock::time_point::max());
            co_await rate_timer_->async_wait(with(error));
            continue;
        }
        rate_timer_->expires_at(pacer_.wake_at());
        co_await rate_timer_->async_wait(with(error));
        if (error || !open()) {
            continue;  // only close() cancels a wake-up under way
        }
        const auto line = pacer_.woken(Clock::now());
        if (line && state_.subscriptions.attitude) {  // it may have unsubscribed meanwhile
            queue_attitude(line);
        }
    }
    pacer_.disarmed();
}

// Over the server's memory budget, a client that has not read what it has
// loses the sample (counted like any drop) instead of queueing more.
void Session::queue_attitude(const AttitudeLine& line) {
    const bool refuse = host_.over_budget() && !outbox_.empty();
    if (const auto dropped = refuse ? outbox_.drop_attitude() : outbox_.push_attitude(line);
        dropped > 0) {
        state_.dropped = outbox_.dropped();
        host_.note_dropped(dropped);
    }
    flush();
}

// ---- writing --------------------------------------------------------------------

// Writes what it can at once; once everything is written, a paused reader
// resumes (on a later turn, so a reply written from inside the core never
// runs a request there) and a closing session closes if no reply is owed.
void Session::flush() {
    if (!write_.pending && !closed()) {
        write_queued();
    }
    sync_budget();
    if (!write_.pending && !closed() && outbox_.empty()) {
        if (std::exchange(paused_, false)) {
            unpause_.cancel();
        }
        finish_if_done();
    }
}

// Most batches fit in the socket's buffer: they are sent at once, with no
// asynchronous operation to set up. Only what does not fit is left to the
// writer coroutine.
void Session::write_queued() {
    while (!outbox_.empty()) {
        if (outbox_.front_descriptors() > 0) {
            if (!send_with_descriptors()) {
                return;  // the writer waits, or closed
            }
            continue;
        }
        write_.lines.clear();
        outbox_.take(write_.lines, kLinesPerWrite);
        write_.cover();
        error_code error;
        const std::size_t sent = socket_.write_some(write_.buffers, error);
        if (error && error != asio::error::would_block && error != asio::error::try_again) {
            close();  // the client went away
            return;
        }
        if (sent < write_.bytes) {
            write_later(sent);
            return;
        }
    }
    write_.clear();
}

// Sends the front line with its descriptors. True: all of it went out and
// the caller writes on. False: the writer waits for room (the line stays
// queued) or writes the rest of the line, or the client is gone.
bool Session::send_with_descriptors() {
    const Line line = outbox_.front();
    const auto fds = host_.channel_descriptors(state_.info);
    if (fds[0] < 0 || fds[1] < 0) {  // cannot happen: the block lives as long as the session
        outbox_.replace_front(std::make_shared<const std::string>(
            detail::unsent_reply(*line, "its descriptors are gone; ask again")));
        host_.channel_delivered(state_.info, EBADF);
        return true;
    }
    const ssize_t sent = base::send_with_descriptors(
        socket_.native_handle(), line->data(), line->size(), fds, MSG_DONTWAIT | MSG_NOSIGNAL);
    if (sent < 0) {
        const int error = errno;
        if (error == EAGAIN || error == EWOULDBLOCK) {
            write_.wait_writable = true;
            write_later(0);
        } else if (error == EPIPE || error == ECONNRESET || error == ENOTCONN) {
            close();
        } else {  // ETOOMANYREFS, ENOMEM, ENOBUFS...: nothing was sent
            outbox_.replace_front(std::make_shared<const std::string>(detail::unsent_reply(
                *line, std::string("sending its descriptors: ") + std::strerror(error))));
            host_.channel_delivered(state_.info, error);
            return true;
        }
        return false;
    }
    host_.channel_delivered(state_.info, 0);
    outbox_.pop_front();
    if (static_cast<std::size_t>(sent) == line->size()) {
        return true;
    }
    write_.lines.assign(1, line);
    write_.cover();
    write_later(static_cast<std::size_t>(sent));
    return false;
}

// Hands the writer what write_some left of the batch in flight (skipping
// `sent` bytes), or the wait for room (write_.wait_writable).
void Session::write_later(std::size_t sent) {
    if (!write_.wait_writable) {
        write_.skip(sent);
    }
    write_.pending = true;
    wake_writer_.cancel();
}

void Session::Write::cover() {
    buffers.clear();
    bytes = 0;
    for (const auto& line : lines) {
        buffers.push_back(asio::buffer(*line));
        bytes += line->size();
    }
}

void Session::Write::skip(std::size_t sent) {
    auto first = buffers.begin();
    while (sent > 0 && sent >= first->size()) {
        sent -= first->size();
        ++first;
    }
    *first += sent;
    buffers.erase(buffers.begin(), first);
}

void Session::Write::clear() {
    pending = wait_writable = false;
    lines.clear();
    buffers.clear();
    bytes = 0;
}

// The one write in flight: sleeps until write_later hands it something,
// writes it (or waits for room), then writes on at once.
Session::Awaitable<void> Session::writer() {
    error_code error;
    while (!closed()) {
        if (!write_.pending) {
            co_await wake_writer_.async_wait(with(error));
            continue;
        }
        if (write_.wait_writable) {
            co_await socket_.async_wait(Socket::wait_write, with(error));
        } else {
            co_await asio::async_write(socket_, write_.buffers, with(error));
        }
        write_.clear();
        if (closed()) {
            co_return;
        }
        if (error) {
            close();  // the client went away mid-write
            co_return;
        }
        flush();
    }
}

void Session::finish_if_done() {
    if (life_ == Life::kClosing && outstanding_ == 0 && !write_.pending && outbox_.empty()) {
        close();
    }
}

// Keeps the server's total of queued bytes (its memory budget) current.
void Session::sync_budget() {
    const std::size_t now = closed() ? 0 : outbox_.bytes() + write_.bytes;
    if (now != accounted_) {
        host_.account(accounted_, now);
        accounted_ = now;
    }
}

}  // namespace gport::ipc
