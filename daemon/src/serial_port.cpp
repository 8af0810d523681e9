#include "gport/daemon/core/serial_port.hpp"

#include <fmt/format.h>
#include <sys/ioctl.h>
#include <termios.h>

#include <algorithm>
#include <boost/asio/post.hpp>
#include <boost/asio/write.hpp>
#include <utility>

#include "gport/daemon/serial_candidates.hpp"

namespace gport::daemon {

namespace asio = boost::asio;
using namespace std::chrono_literals;

SerialPort::SerialPort(asio::io_context& io, const config::SerialConfig& serial,
                       const config::LinkConfig& link, Handlers handlers,
                       std::shared_ptr<spdlog::logger> log)
    : port_(io),
      reopen_timer_(io),
      pace_timer_(io),
      drain_timer_(io),
      device_(serial.device),
      baud_(serial.baud),
      byte_time_(std::chrono::nanoseconds(10'000'000'000LL / std::max(serial.baud, 1u))),
      backoff_initial_(link.reconnect_initial),
      backoff_max_(link.reconnect_max),
      backoff_(link.reconnect_initial),
      handlers_(std::move(handlers)),
      log_(std::move(log)),
      open_failures_log_(60s),
      losses_log_(60s) {}

void SerialPort::start() {
    stopped_ = false;
    try_open();
}

void SerialPort::stop() {
    stopped_ = true;
    reopen_timer_.cancel();
    pace_timer_.cancel();
    pacing_ = false;
    if (port_.is_open()) {
        boost::system::error_code ignored;
        port_.close(ignored);
        log_->info("device {} closed", device_);
        handlers_.on_close("daemon stopping");
    }
    queue_.clear();
    in_flight_.reset();
    owed_stop_.reset();  // the daemon is going away: nothing will reopen
    notify_drained();
}

void SerialPort::try_open() {
    boost::system::error_code ec;
    port_.open(device_, ec);
    std::string error;
    if (!ec && !configure(error)) {
        port_.close(ec);
        ec = asio::error::invalid_argument;
    } else if (ec) {
        error = ec.message();
    }
    if (ec) {
        open_error_ = error;
        ++stats_.failures;
        if (auto count = open_failures_log_.occur()) {
            // A missing device: say which exist and what to set.
            const auto hint = ec == boost::system::errc::no_such_file_or_directory
                                  ? "; " + candidates_hint(serial_candidates())
                                  : std::string();
            log_->warn("cannot open device {}: {} ({} attempt{} since last report); retrying{}",
                       device_, error, *count, *count == 1 ? "" : "s", hint);
        }
        schedule_reopen();
        return;
    }
    ++stats_.opens;
    open_error_.clear();
    healthy_ = false;
    open_failures_log_.reset();
    line_free_at_ = std::chrono::steady_clock::now();
    log_->info("device {} opened at {} baud", device_, baud_);
    handlers_.on_open();
    read_more();
    if (owed_stop_) {
        queue_.push(*std::exchange(owed_stop_, std::nullopt), FrameKind::kStop);
    }
    write_next();
}

// Raw 8N1 without flow control, and exclusive: no other process may open
// the port while the daemon owns it.
bool SerialPort::configure(std::string& error) {
    boost::system::error_code ec;
    port_.set_option(asio::serial_port::baud_rate(baud_), ec);
    if (!ec) {
        port_.set_option(asio::serial_port::character_size(8), ec);
    }
    if (!ec) {
        port_.set_option(asio::serial_port::parity(asio::serial_port::parity::none), ec);
    }
    if (!ec) {
        port_.set_option(asio::serial_port::stop_bits(asio::serial_port::stop_bits::one), ec);
    }
    if (!ec) {
        port_.set_option(asio::serial_port::flow_control(asio::serial_port::flow_control::none),
                         ec);
    }
    if (ec) {
        error = "cannot configure " + std::to_string(baud_) + " 8N1: " + ec.message();
        return false;
    }
    if (::ioctl(port_.native_handle(), TIOCEXCL) != 0) {
        log_->debug("device {}: exclusive mode not available", device_);
    }
    ::tcflush(port_.native_handle(), TCIOFLUSH);
    return true;
}

void SerialPort::schedule_reopen() {
    if (stopped_) {
        return;
    }
    reopen_timer_.expires_after(backoff_);
    backoff_ = std::min(backoff_ * 2, backoff_max_);
    reopen_timer_.async_wait([this](boost::system::error_code ec) {
        if (!ec && !stopped_) {
            try_open();
        }
    });
}

void SerialPort::read_more() {
    port_.async_read_some(asio::buffer(read_buffer_),
                          [this](boost::system::error_code ec, std::size_t n) {
                              if (ec == asio::error::operation_aborted || !port_.is_open()) {
                                  return;
                              }
                              if (ec) {
                                  fail(ec == asio::error::eof ? "device hung up" : ec.message());
                                  return;
                              }
                              if (!healthy_) {
                                  healthy_ = true;
                                  backoff_ = backoff_initial_;
                              }
                              handlers_.on_bytes({read_buffer_.data(), n});
                              if (port_.is_open()) {
                                  read_more();
                              }
                          });
}

bool SerialPort::send(const protocol::Frame& frame, FrameKind kind) {
    if (!port_.is_open()) {
        if (kind == FrameKind::kStop && !stopped_) {
            owed_stop_ = frame;
        }
        return false;
    }
    if (!queue_.push(frame, kind)) {
        return false;
    }
    write_next();
    return true;
}

std::chrono::steady_clock::time_point SerialPort::due_on_wire() {
    const auto now = std::chrono::steady_clock::now();
    if (!port_.is_open()) {
        return now;
    }
    return now + line_ahead(now) + static_cast<long>(queue_.bytes()) * byte_time_;
}

std::chrono::steady_clock::duration SerialPort::line_ahead(
    std::chrono::steady_clock::time_point now) {
    auto ahead = std::max(line_free_at_ - now, std::chrono::steady_clock::duration::zero());
    int queued = 0;  // a pty reports 0; a UART driver its transmit buffer
    if (::ioctl(port_.native_handle(), TIOCOUTQ, &queued) == 0 && queued > 0) {
        ahead = std::max<std::chrono::steady_clock::duration>(ahead, queued * byte_time_);
    }
    return ahead;
}

void SerialPort::write_next() {
    if (in_flight_ || pacing_ || queue_.empty() || !port_.is_open()) {
        return;
    }
    const auto now = std::chrono::steady_clock::now();
    if (const auto ahead = line_ahead(now); ahead > kLineSlack) {
        pacing_ = true;
        pace_timer_.expires_after(ahead - kLineSlack);
        pace_timer_.async_wait([this](boost::system::error_code ec) {
            if (ec == asio::error::operation_aborted) {
                return;  // stop() or fail() cleared pacing_ themselves
            }
            pacing_ = false;
            write_next();
        });
        return;
    }
    in_flight_ = queue_.pop();
    const auto bytes = in_flight_->frame.bytes();
    line_free_at_ = std::max(line_free_at_, now) + static_cast<long>(bytes.size()) * byte_time_;
    asio::async_write(port_, asio::buffer(bytes.data(), bytes.size()),
                      [this](boost::system::error_code ec, std::size_t n) {
                          // Aborted: the port was closed, which already
                          // dropped in_flight_ (and may have reopened since).
                          if (ec == asio::error::operation_aborted || !port_.is_open()) {
                              return;
                          }
                          if (ec) {
                              fail("write failed: " + ec.message());
                              return;
                          }
                          stats_.bytes_out += n;
                          ++stats_.frames_out;
                          if (in_flight_->kind == FrameKind::kStop) {
                              ++stats_.stops_written;
                          }
                          in_flight_.reset();
                          if (queue_.empty()) {
                              notify_drained();
                          }
                          write_next();
                      });
}

void SerialPort::fail(const std::string& reason) {
    ++stats_.failures;
    boost::system::error_code ignored;
    port_.close(ignored);
    pace_timer_.cancel();
    pacing_ = false;
    owe_stop_if_unwritten();
    queue_.clear();
    in_flight_.reset();
    if (auto count = losses_log_.occur()) {
        log_->warn("device {} lost: {} ({} loss{} since last report); reopening", device_, reason,
                   *count, *count == 1 ? "" : "es");
    }
    handlers_.on_close(reason);
    notify_drained();
    schedule_reopen();
}

// A stop the device may not have received completely is written again on
// reopen: a repeated zero speed is harmless, a lost one is not.
void SerialPort::owe_stop_if_unwritten() {
    if (in_flight_ && in_flight_->kind == FrameKind::kStop) {
        owed_stop_ = in_flight_->frame;
    } else if (queue_.holds_stop()) {
        owed_stop_ = queue_.pop().frame;
    }
}

SerialPort::Stats SerialPort::stats() const {
    Stats s = stats_;
    s.queue_overflows = queue_.refused();
    s.frames_replaced = queue_.replaced();
    return s;
}

void SerialPort::drain(std::chrono::milliseconds limit, std::function<void()> done) {
    auto once = [this, called = std::make_shared<bool>(false), done = std::move(done)] {
        if (!std::exchange(*called, true)) {
            drain_timer_.cancel();
            done();
        }
    };
    drain_timer_.expires_after(limit);
    drain_timer_.async_wait([once](boost::system::error_code ec) {
        if (!ec) {
            once();
        }
    });
    // Posted: done() may close the port, which must not happen inside the
    // write completion that found the queue empty.
    auto drained = [this, once] { asio::post(drain_timer_.get_executor(), once); };
    if ((queue_.empty() && !in_flight_) || !port_.is_open()) {
        drained();
    } else {
        drained_waiters_.push_back(std::move(drained));
    }
}

void SerialPort::notify_drained() {
    auto waiters = std::exchange(drained_waiters_, {});
    for (auto& w : waiters) {
        w();
    }
}

CommandError link_down_error(const SerialPort& port, bool closing, std::string_view consequence) {
    std::string why;
    if (!port.is_open()) {
        why = "is not open";
    } else if (closing) {
        why = "is closing: gportd is shutting down";
    } else {
        why = fmt::format("takes no data ({} frames wait for it)", SerialPort::kMaxQueuedFrames);
    }
    return CommandError{ErrorCode::kLinkDown,
                        fmt::format("gimbal link down: serial device {} {}{}{}", port.device(), why,
                                    consequence.empty() ? "" : "; ", consequence)};
}

}  // namespace gport::daemon
