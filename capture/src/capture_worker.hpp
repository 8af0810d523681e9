// CaptureWriter's state, shared (shared_ptr) by the writer and its thread,
// so that a thread left behind at exit on a stalled disk touches nothing
// the process destroys. The queue, the stats and the marks are under the
// mutex; the files and the sync pace are the thread's own.
#pragma once

#include <spdlog/logger.h>

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "gport/capture/capture_writer.hpp"

namespace gport::capture {

class CaptureWorker {
  public:
    using Clock = std::chrono::steady_clock;

    CaptureWorker(CaptureFiles files, std::shared_ptr<spdlog::logger> log, std::size_t queue_limit);
    ~CaptureWorker();
    CaptureWorker(const CaptureWorker&) = delete;
    CaptureWorker& operator=(const CaptureWorker&) = delete;

    // Start-up, before the thread: opens captures.next and writes `mark`.
    void start_mark(std::uint64_t mark);
    // The thread's body: until stop() (or abandoned).
    void run();

    void push(std::string line);
    void reserve(std::uint64_t upto);
    std::optional<std::uint64_t> reserved() const;
    void finish(std::uint64_t next_index);
    CaptureSink::Stats stats() const;
    void drain();
    // Asks the thread to finish and waits up to `wait` for it: true when it
    // finished; false when it was abandoned (the lines not written counted
    // and logged).
    bool stop(std::chrono::milliseconds wait);

  private:
    struct Batch {
        std::deque<std::string> lines;
        bool mark = false;
    };
    bool idle() const;  // under the mutex, as has_work()
    bool has_work() const;
    void wait_for_work(std::unique_lock<std::mutex>& lock);
    Batch take();
    // False when abandoned meanwhile.
    bool write_lines(std::deque<std::string>& lines);
    // An error text, or nullopt when the line was written.
    std::optional<std::string> write_line(const std::string& line);
    void persist_mark();
    // fdatasync when lines are unsynced and (now, or) kSyncInterval passed.
    void sync(bool now);
    std::optional<std::string> open_file();
    void close_file();
    void rotate();
    // Counts `lines` lost (0: an error that lost none) for `message`, keeps it
    // for status and logs it, at most once a kLogInterval with the count.
    void lost(std::uint64_t lines, const std::string& message);
    void report_lost(bool at_exit);

    const CaptureFiles files_;
    const std::shared_ptr<spdlog::logger> log_;
    const std::size_t queue_limit_;

    mutable std::mutex mutex_;
    std::condition_variable wake_;  // the thread: work, a mark, stop
    std::condition_variable idle_;  // drain() and stop()
    std::deque<std::string> queue_;
    std::size_t in_flight_ = 0;  // taken by the thread, not yet written
    bool busy_ = false;
    bool unsynced_ = false;  // lines written since the last fdatasync
    bool mark_pending_ = false;
    bool stopping_ = false;
    bool finished_ = false;
    bool abandoned_ = false;
    std::uint64_t wanted_mark_ = 0;
    std::optional<std::uint64_t> durable_mark_;
    CaptureSink::Stats stats_;
    std::optional<std::string> sticky_error_;  // no durable storage: status says so for good
    // The error stays until a line queued after it is written: lines
    // accepted into the queue, lines the thread has dealt with, and the
    // count accepted at the last loss.
    std::uint64_t accepted_ = 0;
    std::uint64_t taken_ = 0;
    std::uint64_t error_until_ = 0;
    std::uint64_t lost_unlogged_ = 0;
    std::optional<Clock::time_point> last_logged_;

    // The thread's own.
    int fd_ = -1;
    int mark_fd_ = -1;
    std::uint64_t size_ = 0;
    Clock::time_point last_sync_{};
};

}  // namespace gport::capture
