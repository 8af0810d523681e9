#include "session.hpp"

#include <fmt/format.h>

#include <boost/asio/write.hpp>
#include <utility>

#include "gport/ipc/server.hpp"

namespace gport::ipc {
namespace {

namespace asio = boost::asio;

// Lines gathered into one write: enough to amortise the syscall, few enough
// that one write stays short.
constexpr std::size_t kLinesPerWrite = 64;

bool blank(std::string_view line) {
    return line.find_first_not_of(" \t\r") == std::string_view::npos;
}

}  // namespace

Session::Session(Socket socket, daemon::ClientInfo info, Server& server)
    : socket_(std::move(socket)),
      server_(server),
      state_{info, {}, 0},
      outbox_(server.config().queue_limit) {}

void Session::start() {
    // Writes are tried at once (see flush); reads stay asynchronous.
    boost::system::error_code ignored;
    socket_.non_blocking(true, ignored);
    read();
}

void Session::close() {
    if (closed_) {
        return;
    }
    closed_ = true;
    boost::system::error_code ignored;
    socket_.shutdown(Socket::shutdown_both, ignored);
    socket_.close(ignored);
    if (rate_timer_) {
        rate_timer_->cancel();
    }
    pending_attitude_.reset();
    server_.session_closed(*this);
}

// ---- reading --------------------------------------------------------------------

void Session::read() {
    socket_.async_read_some(
        asio::buffer(read_buffer_),
        [self = shared_from_this()](const boost::system::error_code& error, std::size_t size) {
            if (self->closed_ || self->closing_) {
                return;
            }
            if (error) {
                self->close();  // EOF or reset: the client went away
                return;
            }
            self->on_read(size);
        });
}

void Session::on_read(std::size_t size) {
    std::string_view data(read_buffer_.data(), size);
    const std::size_t limit = server_.config().line_limit;
    while (!data.empty() && !closed_ && !closing_) {
        const auto newline = data.find('\n');
        const auto piece = data.substr(0, newline);
        if (partial_.size() + piece.size() > limit) {
            refuse_long_line();
            return;
        }
        partial_.append(piece);
        if (newline == std::string_view::npos) {
            break;
        }
        handle_line(partial_);
        partial_.clear();
        data.remove_prefix(newline + 1);
    }
    if (!closed_ && !closing_) {
        read();
    }
}

void Session::handle_line(std::string& line) {
    if (!line.empty() && line.back() == '\r') {
        line.pop_back();  // tolerate CRLF from terminals
    }
    if (blank(line)) {
        return;
    }
    auto weak = weak_from_this();
    server_.dispatcher().handle_line(line, state_, [weak](std::string reply) {
        if (auto self = weak.lock()) {
            self->reply(std::move(reply));
        }
    });
}

void Session::refuse_long_line() {
    server_.log().warn("client pid {} uid {}: request line longer than {} bytes; closing",
                       state_.info.pid, state_.info.uid, server_.config().line_limit);
    reply(error_line(rpc_error::kInvalidRequest,
                     fmt::format("request line longer than {} bytes; closing the connection",
                                 server_.config().line_limit)));
    closing_ = true;
    partial_.clear();
    partial_.shrink_to_fit();
    flush();
}

// ---- queueing ---------------------------------------------------------------------

void Session::reply(std::string line) {
    if (closed_) {
        return;
    }
    if (!outbox_.push(std::make_shared<const std::string>(std::move(line)))) {
        overflow();
        return;
    }
    flush();
}

void Session::deliver_event(const Line& line) {
    if (closed_ || closing_) {
        return;
    }
    if (!outbox_.push(line)) {
        overflow();
        return;
    }
    flush();
}

void Session::overflow() {
    server_.log().warn("client pid {} uid {}: {} lines wait unread; disconnecting it",
                       state_.info.pid, state_.info.uid, outbox_.size());
    close();
}

void Session::deliver_attitude(const Line& line) {
    if (closed_ || closing_) {
        return;
    }
    const auto& rate = state_.subscriptions.max_rate_hz;
    if (!rate) {
        queue_attitude(line);
        return;
    }
    const auto interval = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(1.0 / *rate));
    const auto now = std::chrono::steady_clock::now();
    if (!timer_armed_ && now - last_attitude_ >= interval) {
        last_attitude_ = now;
        queue_attitude(line);
        return;
    }
    // Too soon: the newest sample waits and replaces any older waiting one.
    pending_attitude_ = line;
    if (timer_armed_) {
        return;
    }
    if (!rate_timer_) {
        rate_timer_.emplace(socket_.get_executor());
    }
    timer_armed_ = true;
    rate_timer_->expires_at(last_attitude_ + interval);
    rate_timer_->async_wait([self = shared_from_this()](const boost::system::error_code& error) {
        self->timer_armed_ = false;
        if (!error) {
            self->on_rate_timer();
        }
    });
}

void Session::on_rate_timer() {
    if (closed_ || closing_ || !pending_attitude_) {
        return;
    }
    last_attitude_ = std::chrono::steady_clock::now();
    auto line = std::move(pending_attitude_);
    pending_attitude_.reset();
    if (state_.subscriptions.attitude) {  // it may have unsubscribed meanwhile
        queue_attitude(line);
    }
}

void Session::queue_attitude(const Line& line) {
    if (const auto dropped = outbox_.push_attitude(line); dropped > 0) {
        state_.dropped = outbox_.dropped();
        server_.note_dropped(dropped);
    }
    flush();
}

// ---- writing ----------------------------------------------------------------------

void Session::flush() {
    if (writing_ || closed_) {
        return;
    }
    // Most batches fit in the socket's buffer: they are sent at once, with no
    // asynchronous operation to set up. Only what does not fit waits for the
    // socket to drain, with one async_write in flight.
    while (!outbox_.empty()) {
        in_flight_.clear();
        outbox_.take(in_flight_, kLinesPerWrite);
        buffers_.clear();
        for (const auto& line : in_flight_) {
            buffers_.push_back(asio::buffer(*line));
        }
        boost::system::error_code error;
        const std::size_t sent = socket_.write_some(buffers_, error);
        if (error && error != asio::error::would_block && error != asio::error::try_again) {
            close();  // the client went away
            return;
        }
        if (sent < asio::buffer_size(buffers_)) {
            write_rest(sent);
            return;
        }
    }
    in_flight_.clear();
    if (closing_) {
        close();
    }
}

// Sends what write_some left of the batch in flight, skipping `sent` bytes.
void Session::write_rest(std::size_t sent) {
    auto first = buffers_.begin();
    while (sent > 0 && sent >= first->size()) {
        sent -= first->size();
        ++first;
    }
    *first += sent;
    buffers_.erase(buffers_.begin(), first);
    writing_ = true;
    asio::async_write(socket_, buffers_,
                      [self = shared_from_this()](const boost::system::error_code& error,
                                                  std::size_t) { self->on_written(error); });
}

void Session::on_written(const boost::system::error_code& error) {
    writing_ = false;
    in_flight_.clear();
    if (closed_) {
        return;
    }
    if (error) {
        close();  // the client went away mid-write
        return;
    }
    flush();
}

}  // namespace gport::ipc
