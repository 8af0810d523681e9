#include <unistd.h>

#include <cerrno>

#include "simulator_impl.hpp"

namespace gport::sim {
namespace {

// One byte on a 115200-baud 8N1 line (10 bits): --pace without --baud.
constexpr auto kByteTime115200 = std::chrono::nanoseconds(86806);
// A UART's transmit buffer: paced output beyond this is dropped, not queued.
constexpr std::size_t kPacedQueueLimit = 4096;

}  // namespace

PtySimulator::Impl::Clock::duration PtySimulator::Impl::byte_time() const {
    if (options_.baud == 0) {
        return kByteTime115200;
    }
    return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(10.0) /
                                                       options_.baud);
}

bool PtySimulator::Impl::can_send() const {
    return device_.is_open() && peer_ && !schedule_.silent() && !schedule_.vanished() && !stopped_;
}

void PtySimulator::Impl::send_frames(const GimbalModel::Frames& frames, Duration now) {
    send(faults_.shape(frames, now));
}

void PtySimulator::Impl::send(std::vector<Chunk> chunks) {
    for (auto& chunk : chunks) {
        if (!can_send()) {
            stats_.bytes_dropped += chunk.size();
            continue;
        }
        if (!paced()) {
            write_now(chunk);
            continue;
        }
        if (queued_bytes_ + chunk.size() > kPacedQueueLimit) {
            stats_.bytes_dropped += chunk.size();
            continue;
        }
        queued_bytes_ += chunk.size();
        queue_.push_back(std::move(chunk));
    }
    if (paced()) {
        pump();
    }
}

// Never blocks: what the pty cannot take now is dropped, as a UART drops
// bytes nobody reads.
void PtySimulator::Impl::write_now(const Chunk& chunk) {
    ssize_t n = -1;
    do {
        n = ::write(device_.native_handle(), chunk.data(), chunk.size());
    } while (n < 0 && errno == EINTR);
    if (n <= 0) {
        stats_.bytes_dropped += chunk.size();
        return;
    }
    const auto written = static_cast<std::size_t>(n);
    stats_.bytes_written += written;
    stats_.bytes_dropped += chunk.size() - written;
    ++stats_.writes;
    record(Direction::kTx, {chunk.data(), written});
}

// Paced output: each write waits until the previous one has left the line.
// `busy`: called by the pacing timer, i.e. the line never went idle.
void PtySimulator::Impl::pump(bool busy) {
    busy = busy || pacing_;  // a pending pacing timer means a backlog: the line is busy
    while (!queue_.empty()) {
        if (!can_send()) {
            for (const auto& c : queue_) {
                stats_.bytes_dropped += c.size();
            }
            queue_.clear();
            queued_bytes_ = 0;
            return;
        }
        const auto now = Clock::now();
        if (now < line_free_) {
            if (!pacing_) {
                pacing_ = true;
                pace_timer_.expires_at(line_free_);
                pace_timer_.async_wait(
                    [self = shared_from_this()](const boost::system::error_code& ec) {
                        self->pacing_ = false;
                        if (!ec && !self->stopped_) {
                            self->pump(true);
                        }
                    });
            }
            return;
        }
        const Chunk chunk = std::move(queue_.front());
        queue_.pop_front();
        queued_bytes_ -= chunk.size();
        write_now(chunk);
        // While the line stays busy (woken to send the next queued write, or
        // catching up in this loop) the next byte time follows the previous
        // one, not the late wake-up, so timer latency does not slow the line.
        const auto base = busy ? line_free_ : std::max(now, line_free_);
        busy = true;
        line_free_ = base + byte_time() * static_cast<std::int64_t>(chunk.size());
    }
}

void PtySimulator::Impl::record(Direction direction, std::span<const std::uint8_t> bytes) {
    if (recorder_) {
        recorder_->write(elapsed(), direction, bytes);
    }
}

}  // namespace gport::sim
