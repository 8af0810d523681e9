// A session's output side: queueing replies and notifications, the attitude
// rate limit, writing with one write in flight, and the memory it holds.
#include <fmt/format.h>
#include <spdlog/logger.h>

#include <boost/asio/write.hpp>
#include <utility>

#include "gport/config/config.hpp"
#include "session.hpp"

namespace gport::ipc {
namespace {

namespace asio = boost::asio;

// Lines gathered into one write: enough to amortise the syscall, few enough
// that one write stays short.
constexpr std::size_t kLinesPerWrite = 64;

}  // namespace

// ---- queueing ---------------------------------------------------------------------

void Session::reply(std::string line, std::size_t descriptors) {
    if (closed()) {
        return;
    }
    const auto size = line.size();
    if (!outbox_.push(std::make_shared<const std::string>(std::move(line)), descriptors)) {
        overflow(size);
        return;
    }
    flush();
}

void Session::deliver_event(const Line& line) {
    if (!open()) {
        return;
    }
    if (!outbox_.push(line)) {
        overflow(line->size());
        return;
    }
    flush();
}

// Only the server is told; the core hears of it after the current event.
void Session::overflow(std::size_t refused_bytes) {
    host_.log().warn(
        "client pid {} uid {}: a line of {} bytes does not fit its output queue ({} lines, {} "
        "bytes wait unread); disconnecting it",
        state_.info.pid, state_.info.uid, refused_bytes, outbox_.size(), outbox_.bytes());
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
    if (!rate_timer_) {
        rate_timer_.emplace(socket_.get_executor());
    }
    rate_timer_->expires_at(pacer_.wake_at());
    rate_timer_->async_wait([self = shared_from_this()](const boost::system::error_code& error) {
        if (error) {
            self->pacer_.disarmed();
        } else {
            self->on_rate_timer();
        }
    });
}

void Session::on_rate_timer() {
    if (!open()) {
        pacer_.disarmed();
        return;
    }
    const auto line = pacer_.woken(Clock::now());
    if (line && state_.subscriptions.attitude) {  // it may have unsubscribed meanwhile
        queue_attitude(line);
    }
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

// ---- writing ----------------------------------------------------------------------

void Session::flush() {
    const auto can_write = [this] { return lifecycle_.output == Output::kIdle && !closed(); };
    if (can_write()) {
        write_queued();
    }
    sync_budget();
    if (can_write() && outbox_.empty()) {
        drained();
    }
}

// Most batches fit in the socket's buffer: they are sent at once, with no
// asynchronous operation to set up. Only what does not fit waits for the
// socket to drain, with one async_write in flight.
void Session::write_queued() {
    while (!outbox_.empty()) {
        if (outbox_.front_descriptors() > 0) {
            if (!send_with_descriptors()) {
                return;  // waiting for the socket, writing the rest, or closed
            }
            continue;
        }
        in_flight_.clear();
        outbox_.take(in_flight_, kLinesPerWrite);
        buffers_.clear();
        in_flight_bytes_ = 0;
        for (const auto& line : in_flight_) {
            buffers_.push_back(asio::buffer(*line));
            in_flight_bytes_ += line->size();
        }
        boost::system::error_code error;
        const std::size_t sent = socket_.write_some(buffers_, error);
        if (error && error != asio::error::would_block && error != asio::error::try_again) {
            close();  // the client went away
            return;
        }
        if (sent < in_flight_bytes_) {
            write_rest(sent);
            return;
        }
    }
    in_flight_.clear();
    in_flight_bytes_ = 0;
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
    advance(SessionEvent::kWriteStarted);
    asio::async_write(socket_, buffers_,
                      [self = shared_from_this()](const boost::system::error_code& error,
                                                  std::size_t) { self->on_written(error); });
}

void Session::on_written(const boost::system::error_code& error) {
    advance(SessionEvent::kWritten);
    in_flight_.clear();
    in_flight_bytes_ = 0;
    if (closed()) {
        return;
    }
    if (error) {
        close();  // the client went away mid-write
        return;
    }
    flush();
}

// Everything queued is written: paused requests resume (on a later turn, so
// a reply written from inside the core never runs a request there), and a
// closing session closes once no reply is owed.
void Session::drained() {
    if (lifecycle_.input == Input::kPaused) {
        post_input(SessionEvent::kUnpaused);
    }
    finish_if_done();
}

void Session::finish_if_done() {
    if (lifecycle_.life == Life::kClosing && outstanding_ == 0 &&
        lifecycle_.output == Output::kIdle && outbox_.empty()) {
        close();
    }
}

// Keeps the server's total of queued bytes (its memory budget) current.
void Session::sync_budget() {
    const std::size_t now = closed() ? 0 : outbox_.bytes() + in_flight_bytes_;
    if (now != accounted_) {
        host_.account(accounted_, now);
        accounted_ = now;
    }
}

}  // namespace gport::ipc
