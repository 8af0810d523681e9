// A session's life cycle and input side: reading, bounded request handling
// per turn, back-pressure, half-close and the idle timeout.
#include "session.hpp"

#include <fmt/format.h>
#include <spdlog/logger.h>

#include <boost/asio/post.hpp>
#include <cassert>
#include <utility>

#include "gport/config/config.hpp"

namespace gport::ipc {
namespace {

namespace asio = boost::asio;

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
      idle_timer_(socket_.get_executor()),
      throttle_timer_(socket_.get_executor()),
      last_request_(Clock::now()) {}

void Session::start() {
    // Writes are tried at once (see flush); reads stay asynchronous.
    boost::system::error_code ignored;
    socket_.non_blocking(true, ignored);
    arm_idle_timer(host_.config().idle_timeout);
    read();
}

void Session::close() {
    if (closed()) {
        return;
    }
    advance(SessionEvent::kClosed);
    boost::system::error_code ignored;
    socket_.shutdown(Socket::shutdown_both, ignored);
    socket_.close(ignored);
    idle_timer_.cancel();
    throttle_timer_.cancel();
    if (rate_timer_) {
        rate_timer_->cancel();
    }
    pacer_.clear();
    sync_budget();
    host_.session_closed(*this);
}

// A refused event means the session's code broke its own table: loud in
// every build (the log), fatal in a debug build.
bool Session::advance(SessionEvent event) {
    if (const auto next = transition(lifecycle_, event)) {
        lifecycle_ = *next;
        return true;
    }
    host_.log().error("client {} (pid {}): session event {} is illegal in state {}; ignored",
                      state_.info.id, state_.info.pid, to_string(event), to_string(lifecycle_));
    assert(!"illegal session transition (session_state.cpp)");
    return false;
}

// ---- reading --------------------------------------------------------------------

void Session::read() {
    if (!advance(SessionEvent::kReadStarted)) {
        return;
    }
    socket_.async_read_some(
        asio::buffer(read_buffer_),
        [self = shared_from_this()](const boost::system::error_code& error, std::size_t size) {
            self->on_read(error, size);
        });
}

void Session::on_read(const boost::system::error_code& error, std::size_t size) {
    advance(SessionEvent::kReadDone);
    if (!open()) {
        return;
    }
    if (error == asio::error::eof) {
        hang_up();
    } else if (error) {
        close();  // reset: the client cannot read replies either
    } else {
        input_.append(read_buffer_.data(), size);
        process_input();
    }
}

// Runs process_input on a later turn, once: `event` is kYielded (a turn's
// worth handled) or kUnpaused (a paused client has read its replies).
void Session::post_input(SessionEvent event) {
    if (!advance(event)) {
        return;
    }
    asio::post(socket_.get_executor(), [self = shared_from_this()] {
        self->advance(SessionEvent::kResumed);
        self->process_input();
    });
}

// Handles up to kLinesPerTurn complete lines, then yields; reads more only
// when no complete line is left and the client's replies are drained.
void Session::process_input() {
    if (!open() || lifecycle_.input != Input::kIdle) {
        return;
    }
    const std::size_t limit = host_.config().line_limit;
    std::size_t handled = 0;
    while (open()) {
        if (backlogged()) {
            advance(SessionEvent::kBacklogged);  // drained() resumes
            return;
        }
        const auto newline = input_.find('\n', consumed_);
        if (newline == std::string::npos) {
            break;
        }
        if (newline - consumed_ > limit) {
            refuse_long_line();
            return;
        }
        if (handled++ == kLinesPerTurn) {
            post_input(SessionEvent::kYielded);
            return;
        }
        if (handled == 1) {
            last_request_ = Clock::now();
        }
        const std::string_view line(input_.data() + consumed_, newline - consumed_);
        consumed_ = newline + 1;
        handle_line(line);
        if (throttle()) {
            return;
        }
    }
    if (!open()) {
        return;
    }
    input_.erase(0, std::exchange(consumed_, 0));
    if (input_.size() > limit) {
        refuse_long_line();
        return;
    }
    read();
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
            self->request_done();
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
bool Session::throttle() {
    const auto& rate = state_.rate;
    if (rate.has_token(Clock::now()) || !open()) {
        return false;
    }
    const auto wait = rate.wait_for(static_cast<double>(kMaxBatch), Clock::now());
    if (wait <= Clock::duration::zero()) {
        return false;
    }
    if (!advance(SessionEvent::kThrottled)) {
        return false;
    }
    throttle_timer_.expires_after(wait);
    throttle_timer_.async_wait([self = shared_from_this()](const boost::system::error_code& error) {
        self->advance(SessionEvent::kThrottleEnded);
        if (!error) {
            self->process_input();
        }
    });
    return true;
}

void Session::request_done() {
    --outstanding_;
    finish_if_done();
}

bool Session::backlogged() const {
    const std::size_t queued = outbox_.reply_bytes() + in_flight_bytes_;
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
        advance(SessionEvent::kRefused);
    }
    input_.clear();
    input_.shrink_to_fit();
    flush();
}

// EOF: a last line without '\n' still counts; the deadman runs now; the
// connection closes once the replies owed are written (finish_if_done).
void Session::hang_up() {
    const std::string_view rest = std::string_view(input_).substr(consumed_);
    if (rest.size() <= host_.config().line_limit) {
        handle_line(rest);
        if (closed()) {
            return;  // it overflowed: closing already told the server
        }
    }
    advance(SessionEvent::kHungUp);
    input_.clear();
    input_.shrink_to_fit();
    host_.client_hung_up(*this);
    flush();
}

// ---- idle timeout -------------------------------------------------------------------

void Session::arm_idle_timer(Clock::duration after) {
    idle_timer_.expires_after(after);
    idle_timer_.async_wait([self = shared_from_this()](const boost::system::error_code& error) {
        if (!error) {
            self->on_idle_timer();
        }
    });
}

// Armed once per timeout, not per request: it looks at the last request when
// it fires.
void Session::on_idle_timer() {
    if (!open()) {
        return;
    }
    const auto timeout = host_.config().idle_timeout;
    const auto quiet = Clock::now() - last_request_;
    if (quiet < timeout) {
        arm_idle_timer(timeout - quiet);
        return;
    }
    if (busy()) {
        arm_idle_timer(timeout);
        return;
    }
    host_.log().info("client {} (pid {} uid {}) idle for {} ms; closing it", state_.info.id,
                     state_.info.pid, state_.info.uid, timeout.count());
    close_after_reply(
        rpc_error::kNoSlot,
        fmt::format("idle for {} ms with no subscription (socket.idle_timeout_ms); closing",
                    timeout.count()));
}

// Quiet is fine for a client that listens (on the socket or through the
// attitude channel), waits for an answer, holds control or owns a motion:
// closing it would stop the gimbal or lose data.
bool Session::busy() const {
    const auto& s = state_.subscriptions;
    return s.attitude || s.link || s.motion || state_.attitude_channel || outstanding_ > 0 ||
           host_.holds_control_or_motion(state_.info);
}

}  // namespace gport::ipc
