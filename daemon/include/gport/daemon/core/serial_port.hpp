// The serial device: opened raw at the configured baud, read continuously,
// written through a queue with one write in flight (the loop never blocks;
// write_queue.hpp says which frames wait and which replace each other),
// and reopened with capped exponential backoff whenever it fails or vanishes.
//
// Writes are paced at the line rate: a frame goes to the kernel only once
// the bytes before it are (nearly) on the wire, by gportd's own account of
// the line (10 bits a byte at the configured baud) and by the driver's
// (TIOCOUTQ, where it reports one). So the backlog of a flood waits in
// gportd's queue, where a stop goes first, not in the kernel's buffer,
// where it would wait behind every frame handed over before it: a stop
// waits at most for the frame already on the wire.
#pragma once

#include <spdlog/logger.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/serial_port.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "gport/base/repeat_limiter.hpp"
#include "gport/config/config.hpp"
#include "gport/daemon/core/write_queue.hpp"
#include "gport/daemon/outcome.hpp"
#include "gport/protocol/frame.hpp"

namespace gport::daemon {

class SerialPort {
  public:
    struct Handlers {
        std::function<void(std::span<const std::uint8_t>)> on_bytes;
        std::function<void()> on_open;
        std::function<void(const std::string& reason)> on_close;
    };

    struct Stats {
        std::uint64_t bytes_out = 0;
        std::uint64_t frames_out = 0;
        std::uint64_t opens = 0;
        std::uint64_t failures = 0;         // failed opens and lost devices
        std::uint64_t queue_overflows = 0;  // frames refused: the device took nothing
        std::uint64_t frames_replaced = 0;  // waiting 0x85 frames a newer one replaced
        std::uint64_t stops_written = 0;    // zero-speed frames written to the device
    };

    // At most this many camera and settings frames wait for the device; more
    // means it is stuck. 0x85 frames are never refused (write_queue.hpp).
    static constexpr std::size_t kMaxQueuedFrames = 64;
    // The next frame goes to the kernel once the bytes before it will be on
    // the wire within this: a stop then waits at most for this, the frame
    // being written (a 22-byte 0x85 is 1.9 ms at 115200 baud) and itself.
    static constexpr auto kLineSlack = std::chrono::milliseconds(1);

    SerialPort(boost::asio::io_context& io, const config::SerialConfig& serial,
               const config::LinkConfig& link, Handlers handlers,
               std::shared_ptr<spdlog::logger> log);

    void start();  // opens now, or keeps retrying in the background
    void stop();   // closes, and stops retrying

    bool is_open() const { return port_.is_open(); }
    const std::string& device() const { return device_; }
    // Why the last attempt to open the device failed ("No such file or
    // directory"); empty once it opened.
    const std::string& open_error() const { return open_error_; }
    Stats stats() const;

    // Queues a frame for the device. False when the device is closed, or for
    // a kOther frame when the device is stuck. A stop that cannot be written
    // because the device is closed (or closes before it is written) is owed:
    // it is the first frame written when the device opens again.
    bool send(const protocol::Frame& frame, FrameKind kind = FrameKind::kOther);
    // Calls done once, from the loop (never inside a completion of the
    // port's own), when every queued frame is written, the device is
    // closed, or `limit` passed: a shutdown's bounded wait for its stop.
    void drain(std::chrono::milliseconds limit, std::function<void()> done);
    // When the last byte of the frames queued so far is due on the wire, by
    // the account that paces the writes (the kernel's buffer, gportd's
    // queue, 10 bits a byte): right after send(), the instant that frame's
    // last byte leaves. A stop sent later goes ahead of a waiting frame and
    // moves it by one 0x85 frame at most (1.9 ms at 115200 baud).
    std::chrono::steady_clock::time_point due_on_wire();

  private:
    void try_open();
    bool configure(std::string& error);
    void schedule_reopen();
    void read_more();
    void write_next();
    // How long until the bytes already handed to the kernel are on the wire.
    std::chrono::steady_clock::duration line_ahead(std::chrono::steady_clock::time_point now);
    void fail(const std::string& reason);
    void notify_drained();
    void owe_stop_if_unwritten();

    boost::asio::serial_port port_;
    boost::asio::steady_timer reopen_timer_;
    boost::asio::steady_timer pace_timer_;
    boost::asio::steady_timer drain_timer_;
    std::string device_;
    unsigned baud_;
    std::chrono::nanoseconds byte_time_;  // one byte on the wire: 10 bits (8N1)
    std::chrono::steady_clock::time_point line_free_at_{};
    bool pacing_ = false;  // pace_timer_ is waiting for the line
    config::Millis backoff_initial_;
    config::Millis backoff_max_;
    config::Millis backoff_;
    Handlers handlers_;
    std::shared_ptr<spdlog::logger> log_;
    base::RepeatLimiter open_failures_log_;
    base::RepeatLimiter losses_log_;
    std::array<std::uint8_t, 4096> read_buffer_{};
    WriteQueue queue_{kMaxQueuedFrames};
    std::optional<WriteQueue::Entry> in_flight_;  // its bytes are what async_write reads
    std::optional<protocol::Frame> owed_stop_;
    bool stopped_ = true;
    bool healthy_ = false;  // bytes arrived since the last open
    std::string open_error_;
    std::vector<std::function<void()>> drained_waiters_;
    Stats stats_;
};

// The one kLinkDown error for a frame that could not be queued: names the
// device and why nothing goes to it (not open; `closing`: gportd is shutting
// down; else it takes no data), then what follows for this request (may be
// empty).
CommandError link_down_error(const SerialPort& port, bool closing = false,
                             std::string_view consequence = {});

}  // namespace gport::daemon
