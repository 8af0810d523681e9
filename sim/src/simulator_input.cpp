// What the client writes, read at once or, with --baud, at the line rate: a
// gimbal's UART takes one byte every 10 bits, so a faster writer's bytes
// wait in the pty's buffer, and a received frame counts from when its last
// byte would have arrived.
#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>

#include "simulator_impl.hpp"

namespace gport::sim {
namespace {

namespace asio = boost::asio;

// --baud: while bytes wait, the line is looked at this often (or when the
// last of them has arrived, if sooner). A frame's time does not depend on
// it: each byte is stamped with its own arrival.
constexpr auto kLineStep = std::chrono::milliseconds(1);

constexpr std::size_t kReadChunk = 4096;

}  // namespace

// Reads are only awaited while a client is there: with no slave open the
// master is permanently readable (POLLHUP) and would spin the loop.
void PtySimulator::Impl::arm_read() {
    if (line_waiting_) {
        return;  // the line timer reads next
    }
    reading_ = true;
    device_.async_wait(
        asio::posix::stream_descriptor::wait_read,
        [self = shared_from_this()](const boost::system::error_code& ec) {
            self->reading_ = false;
            if (!ec && !self->stopped_ && !self->paused_ && self->device_.is_open()) {
                self->on_readable();
            }
        });
}

void PtySimulator::Impl::on_readable() {
    if (options_.baud > 0) {
        read_at_line_rate();
    } else {
        read_all();
    }
}

void PtySimulator::Impl::read_all() {
    std::array<std::uint8_t, kReadChunk> buf{};
    for (;;) {
        const auto n = ::read(device_.native_handle(), buf.data(), buf.size());
        if (n > 0) {
            handle_input({buf.data(), static_cast<std::size_t>(n)});
            if (!device_.is_open()) {
                return;
            }
            continue;
        }
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
            if (!paused_) {
                arm_read();
            }
            return;
        }
        input_failed();
        return;
    }
}

// EIO (or EOF): the client closed the slave. The tick notices when one opens
// it again and re-arms the read.
void PtySimulator::Impl::input_failed() {
    if (peer_) {
        peer_gone();
    }
}

// Reads only the bytes that have fully arrived by now at the line rate, the
// first of a burst starting when it is seen on an idle line; the rest stay in
// the pty, and the line timer comes back for them.
void PtySimulator::Impl::read_at_line_rate() {
    const int fd = device_.native_handle();
    int queued = 0;
    if (::ioctl(fd, FIONREAD, &queued) != 0 || queued <= 0) {
        rx_backlog_ = false;
        if (!peer_present(fd)) {
            input_failed();
        } else if (!paused_) {
            arm_read();
        }
        return;
    }
    stats_.read_backlog_max =
        std::max<std::uint64_t>(stats_.read_backlog_max, static_cast<std::uint64_t>(queued));
    const auto now = Clock::now();
    if (!rx_backlog_) {
        rx_line_ = std::max(rx_line_, now);
    }
    const auto byte = byte_time();
    const auto arrived = now > rx_line_ ? static_cast<std::size_t>((now - rx_line_) / byte) : 0;
    const auto want = std::min({static_cast<std::size_t>(queued), arrived, kReadChunk});
    std::array<std::uint8_t, kReadChunk> buf{};
    ssize_t n = 0;
    if (want > 0) {
        do {
            n = ::read(fd, buf.data(), want);
        } while (n < 0 && errno == EINTR);
        if (n <= 0) {
            input_failed();
            return;
        }
        const auto first_done = rx_line_ + byte;
        rx_line_ += byte * n;
        handle_at_line_rate({buf.data(), static_cast<std::size_t>(n)}, first_done);
        if (!device_.is_open()) {
            return;
        }
    }
    const auto left = static_cast<std::size_t>(queued) - static_cast<std::size_t>(n);
    rx_backlog_ = left > 0;
    if (!rx_backlog_) {
        arm_read();
        return;
    }
    const auto step = std::max<Clock::duration>(byte, kLineStep);
    wait_for_line(rx_line_ +
                  std::min<Clock::duration>(byte * static_cast<std::int64_t>(left), step));
}

void PtySimulator::Impl::wait_for_line(Clock::time_point at) {
    line_waiting_ = true;
    line_timer_.expires_at(at);
    line_timer_.async_wait([self = shared_from_this()](const boost::system::error_code& ec) {
        self->line_waiting_ = false;
        if (!ec && !self->stopped_ && !self->paused_ && self->device_.is_open()) {
            self->read_at_line_rate();
        }
    });
}

// A gimbal whose UART stops draining: the bytes stay in the kernel's pty
// buffer and, once it is full, the client's writes block (or time out).
void PtySimulator::Impl::pause_reading() {
    if (!paused_) {
        paused_ = true;
        event("reading_paused", slave_path_);
    }
}

void PtySimulator::Impl::resume_reading() {
    if (!paused_) {
        return;
    }
    paused_ = false;
    event("reading_resumed", slave_path_);
    if (peer_ && !reading_ && device_.is_open()) {
        arm_read();
    }
}

void PtySimulator::Impl::handle_input(std::span<const std::uint8_t> bytes) {
    const Duration now = elapsed();
    stats_.bytes_read += bytes.size();
    record(Direction::kRx, bytes);
    auto due = model_.step(now);  // commands act at the time they arrive
    auto replies = model_.receive(bytes);
    if (replay_.empty()) {
        due.insert(due.end(), replies.begin(), replies.end());
        send_frames(due, now);
    }
}

// As handle_input(), but the model sees the bytes one at a time, each traced
// at its own arrival (`first_done` is the first one's), so a frame's time is
// its last byte's, not the read's.
void PtySimulator::Impl::handle_at_line_rate(std::span<const std::uint8_t> bytes,
                                             Clock::time_point first_done) {
    const Duration now = elapsed();
    stats_.bytes_read += bytes.size();
    record(Direction::kRx, bytes);
    auto due = model_.step(now);
    const auto byte = byte_time();
    for (std::size_t i = 0; i < bytes.size(); ++i) {
        rx_trace_time_ = first_done + byte * static_cast<std::int64_t>(i) - start_;
        auto replies = model_.receive(bytes.subspan(i, 1));
        due.insert(due.end(), replies.begin(), replies.end());
    }
    rx_trace_time_.reset();
    if (replay_.empty()) {
        send_frames(due, now);
    }
}

}  // namespace gport::sim
