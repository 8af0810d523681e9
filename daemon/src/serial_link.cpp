#include "serial_link.hpp"

#include <sys/ioctl.h>
#include <termios.h>

#include <algorithm>
#include <boost/asio/write.hpp>
#include <utility>

namespace gport::daemon {

namespace asio = boost::asio;
using namespace std::chrono_literals;

SerialLink::SerialLink(asio::io_context& io, const config::SerialConfig& serial,
                       const config::LinkConfig& link, Handlers handlers,
                       std::shared_ptr<spdlog::logger> log)
    : port_(io),
      reopen_timer_(io),
      device_(serial.device),
      baud_(serial.baud),
      backoff_initial_(link.reconnect_initial),
      backoff_max_(link.reconnect_max),
      backoff_(link.reconnect_initial),
      handlers_(std::move(handlers)),
      log_(std::move(log)),
      open_failures_log_(60s),
      losses_log_(60s) {}

void SerialLink::start() {
    stopped_ = false;
    try_open();
}

void SerialLink::stop() {
    stopped_ = true;
    reopen_timer_.cancel();
    if (port_.is_open()) {
        boost::system::error_code ignored;
        port_.close(ignored);
        log_->info("device {} closed", device_);
        handlers_.on_close("daemon stopping");
    }
    queue_.clear();
    writing_ = false;
    notify_drained();
}

void SerialLink::try_open() {
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
        ++stats_.failures;
        if (auto count = open_failures_log_.occur()) {
            log_->warn("cannot open device {}: {} ({} attempt{} since last report); retrying",
                       device_, error, *count, *count == 1 ? "" : "s");
        }
        schedule_reopen();
        return;
    }
    ++stats_.opens;
    healthy_ = false;
    open_failures_log_.reset();
    log_->info("device {} opened at {} baud", device_, baud_);
    handlers_.on_open();
    read_more();
    write_next();
}

// Raw 8N1 without flow control, and exclusive: no other process may open
// the port while the daemon owns it.
bool SerialLink::configure(std::string& error) {
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

void SerialLink::schedule_reopen() {
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

void SerialLink::read_more() {
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

bool SerialLink::send(const protocol::Frame& frame) {
    if (!port_.is_open()) {
        return false;
    }
    if (queue_.size() >= kMaxQueuedFrames) {
        ++stats_.queue_overflows;
        return false;
    }
    queue_.push_back(frame);
    write_next();
    return true;
}

void SerialLink::write_next() {
    if (writing_ || queue_.empty() || !port_.is_open()) {
        return;
    }
    writing_ = true;
    asio::async_write(port_, asio::buffer(queue_.front().bytes().data(), queue_.front().size()),
                      [this](boost::system::error_code ec, std::size_t n) {
                          writing_ = false;
                          if (ec == asio::error::operation_aborted || !port_.is_open()) {
                              return;
                          }
                          if (ec) {
                              fail("write failed: " + ec.message());
                              return;
                          }
                          stats_.bytes_out += n;
                          ++stats_.frames_out;
                          queue_.pop_front();
                          if (queue_.empty()) {
                              notify_drained();
                          }
                          write_next();
                      });
}

void SerialLink::fail(const std::string& reason) {
    ++stats_.failures;
    boost::system::error_code ignored;
    port_.close(ignored);
    queue_.clear();
    writing_ = false;
    if (auto count = losses_log_.occur()) {
        log_->warn("device {} lost: {} ({} loss{} since last report); reopening", device_, reason,
                   *count, *count == 1 ? "" : "es");
    }
    handlers_.on_close(reason);
    notify_drained();
    schedule_reopen();
}

void SerialLink::when_drained(std::function<void()> done) {
    if (queue_.empty() || !port_.is_open()) {
        done();
        return;
    }
    drained_waiters_.push_back(std::move(done));
}

void SerialLink::notify_drained() {
    auto waiters = std::exchange(drained_waiters_, {});
    for (auto& w : waiters) {
        w();
    }
}

}  // namespace gport::daemon
