#include "capture_worker.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <utility>

#include "capture_mark.hpp"

namespace gport::capture {
namespace {

constexpr auto kLogInterval = std::chrono::minutes(1);

// Back to blocking writes: the thread is there to wait for the disk.
void set_blocking(int fd) {
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
}

}  // namespace

CaptureWorker::CaptureWorker(CaptureFiles files, std::shared_ptr<spdlog::logger> log,
                             std::size_t queue_limit)
    : files_(std::move(files)), log_(std::move(log)), queue_limit_(queue_limit) {}

CaptureWorker::~CaptureWorker() {
    for (const int fd : {fd_, mark_fd_}) {
        if (fd >= 0) {
            ::close(fd);
        }
    }
}

void CaptureWorker::start_mark(std::uint64_t mark) {
    mark = std::min(mark, kMaxCaptureIndex + 1);
    const auto path = files_.mark();
    mark_fd_ = open_mark(path);
    const int error = errno;
    auto failure = mark_fd_ < 0
                       ? std::optional(error == EINVAL ? "not a regular file" : open_error(error))
                       : write_mark(mark_fd_, mark);
    const std::lock_guard lock(mutex_);
    if (!failure) {
        wanted_mark_ = mark;
        durable_mark_ = mark;
        return;
    }
    if (mark_fd_ >= 0) {
        ::close(mark_fd_);
        mark_fd_ = -1;
    }
    sticky_error_ = fmt::format(
        "cannot write {}: {}; the capture log has no durable storage (its indexes may repeat "
        "after a restart)",
        path, *failure);
    stats_.error = sticky_error_;
    log_->warn("capture log: {}", *sticky_error_);
}

void CaptureWorker::push(std::string line) {
    {
        const std::lock_guard lock(mutex_);
        if (queue_.size() < queue_limit_) {
            queue_.push_back(std::move(line));
            ++accepted_;
            wake_.notify_one();
            return;
        }
    }
    lost(1, fmt::format("queue full ({} lines): the disk does not keep up with {}", queue_limit_,
                        files_.file(0)));
}

void CaptureWorker::reserve(std::uint64_t upto) {
    upto = std::min(upto, kMaxCaptureIndex + 1);
    const std::lock_guard lock(mutex_);
    if (!durable_mark_ || upto <= *durable_mark_) {
        return;  // no durable storage, or made durable already
    }
    wanted_mark_ = std::max(wanted_mark_, upto);
    mark_pending_ = true;  // again after a failure: each call retries
    wake_.notify_one();
}

void CaptureWorker::finish(std::uint64_t next_index) {
    const std::lock_guard lock(mutex_);
    if (!durable_mark_) {
        return;
    }
    wanted_mark_ = std::min(next_index, kMaxCaptureIndex + 1);  // lowered: nothing is given past it
    mark_pending_ = true;
    wake_.notify_one();
}

std::optional<std::uint64_t> CaptureWorker::reserved() const {
    const std::lock_guard lock(mutex_);
    return durable_mark_;
}

CaptureSink::Stats CaptureWorker::stats() const {
    const std::lock_guard lock(mutex_);
    return stats_;
}

void CaptureWorker::drain() {
    std::unique_lock lock(mutex_);
    idle_.wait(lock, [this] { return finished_ || idle(); });
}

bool CaptureWorker::stop(std::chrono::milliseconds wait) {
    std::unique_lock lock(mutex_);
    stopping_ = true;
    wake_.notify_one();
    if (idle_.wait_for(lock, wait, [this] { return finished_; })) {
        lock.unlock();
        report_lost(true);
        return true;
    }
    abandoned_ = true;
    const auto unwritten = queue_.size() + in_flight_;
    stats_.dropped += unwritten;
    queue_.clear();
    lock.unlock();
    report_lost(true);
    log_->error(
        "capture log: {} line(s) not written: {} did not take them within {} ms (a stalled "
        "disk); exiting without them",
        unwritten, files_.file(0), wait.count());
    return false;
}

bool CaptureWorker::idle() const {
    return queue_.empty() && !busy_ && !unsynced_ && !mark_pending_;
}

bool CaptureWorker::has_work() const {
    return stopping_ || !queue_.empty() || mark_pending_;
}

void CaptureWorker::wait_for_work(std::unique_lock<std::mutex>& lock) {
    if (unsynced_) {  // or until the group's fdatasync is due
        wake_.wait_until(lock, last_sync_ + CaptureWriter::kSyncInterval,
                         [this] { return has_work(); });
    } else {
        wake_.wait(lock, [this] { return has_work(); });
    }
}

void CaptureWorker::run() {
    std::unique_lock lock(mutex_);
    for (;;) {
        wait_for_work(lock);
        if (abandoned_) {
            return;
        }
        if (stopping_ && queue_.empty() && !mark_pending_ && !unsynced_) {
            finished_ = true;
            idle_.notify_all();
            return;
        }
        auto batch = take();
        const bool stopping = stopping_;
        lock.unlock();
        if (!write_lines(batch.lines)) {
            return;  // abandoned at exit while it waited for the disk
        }
        if (batch.mark) {
            persist_mark();
        }
        sync(stopping);
        report_lost(false);
        lock.lock();
        busy_ = false;
        if (idle()) {
            idle_.notify_all();
        }
    }
}

CaptureWorker::Batch CaptureWorker::take() {
    Batch batch;
    batch.lines.swap(queue_);
    batch.mark = std::exchange(mark_pending_, false);
    in_flight_ = batch.lines.size();
    busy_ = true;
    return batch;
}

bool CaptureWorker::write_lines(std::deque<std::string>& lines) {
    for (auto& line : lines) {
        const auto error = write_line(line);
        if (error) {
            lost(1, *error);
        }
        const std::lock_guard lock(mutex_);
        if (abandoned_) {
            return false;  // counted by stop()
        }
        --in_flight_;
        ++taken_;
        if (!error) {
            ++stats_.written;
            unsynced_ = true;
            if (taken_ > error_until_) {  // queued after the last loss: the disk is back
                stats_.error = sticky_error_;
            }
        }
    }
    return true;
}

std::optional<std::string> CaptureWorker::write_line(const std::string& line) {
    if (fd_ >= 0 && size_ > 0 && size_ + line.size() + 1 > files_.max_file_bytes) {
        rotate();
    }
    if (fd_ < 0) {
        if (auto error = open_file()) {
            return error;
        }
    }
    const std::string text = line + '\n';
    std::size_t done = 0;
    while (done < text.size()) {
        const auto n = ::write(fd_, text.data() + done, text.size() - done);
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n <= 0) {
            const int error = n < 0 ? errno : ENOSPC;
            size_ += done;
            close_file();  // reopened (and the cut line ended) for the next capture
            return fmt::format("cannot write {}: {}", files_.file(0), std::strerror(error));
        }
        done += static_cast<std::size_t>(n);
    }
    size_ += done;
    return std::nullopt;
}

void CaptureWorker::persist_mark() {
    std::uint64_t mark = 0;
    {
        const std::lock_guard lock(mutex_);
        mark = wanted_mark_;
    }
    if (auto error = write_mark(mark_fd_, mark)) {
        lost(0, fmt::format("cannot write {}: {}; captures past the reserved index are refused "
                            "until it can be",
                            files_.mark(), *error));
        return;
    }
    const std::lock_guard lock(mutex_);
    durable_mark_ = mark;  // what the file holds now
}

void CaptureWorker::sync(bool now) {
    {
        const std::lock_guard lock(mutex_);
        if (!unsynced_) {
            return;
        }
    }
    const auto time = Clock::now();
    if (!now && time < last_sync_ + CaptureWriter::kSyncInterval) {
        return;
    }
    // EINVAL: a file that cannot be synced (a FIFO): nothing is lost by that.
    if (fd_ >= 0 && ::fdatasync(fd_) != 0 && errno != EINVAL) {
        lost(0, fmt::format("cannot sync {}: {}; the lines written in the last {} ms may be lost",
                            files_.file(0), std::strerror(errno),
                            CaptureWriter::kSyncInterval.count()));
    }
    last_sync_ = time;
    const std::lock_guard lock(mutex_);
    unsynced_ = false;
}

std::optional<std::string> CaptureWorker::open_file() {
    const auto path = files_.file(0);
    fd_ = open_no_follow(path, O_RDWR | O_APPEND | O_CREAT | O_EXCL);  // RDWR: pread
    if (fd_ >= 0) {
        ::fchmod(fd_, 0640);  // whatever the umask: its group may read it
    } else if (errno == EEXIST) {
        fd_ = open_no_follow(path, O_RDWR | O_APPEND);
    }
    if (fd_ < 0) {
        return fmt::format("cannot open {}: {}", path, open_error(errno));
    }
    set_blocking(fd_);
    struct stat st {};
    size_ =
        ::fstat(fd_, &st) == 0 && S_ISREG(st.st_mode) ? static_cast<std::uint64_t>(st.st_size) : 0;
    char last = '\n';
    if (size_ > 0 && ::pread(fd_, &last, 1, static_cast<off_t>(size_ - 1)) == 1 && last != '\n') {
        // A line cut short (a crash, a full disk): end it, so the next one stands alone.
        if (::write(fd_, "\n", 1) == 1) {
            ++size_;
        }
    }
    return std::nullopt;
}

void CaptureWorker::close_file() {
    if (fd_ < 0) {
        return;
    }
    sync(true);  // the lines of a rotated file are on the disk before it is renamed
    ::close(fd_);
    fd_ = -1;
}

void CaptureWorker::rotate() {
    close_file();
    for (int n = files_.keep_files - 1; n >= 1; --n) {
        // The oldest is replaced by the one before it; a missing one is no error.
        std::rename(files_.file(n - 1).c_str(), files_.file(n).c_str());
    }
}

void CaptureWorker::lost(std::uint64_t lines, const std::string& message) {
    std::uint64_t count = 0;
    {
        const std::lock_guard lock(mutex_);
        stats_.dropped += lines;
        stats_.error = message;
        error_until_ = accepted_;
        lost_unlogged_ += lines;
        const auto now = Clock::now();
        if (last_logged_ && now - *last_logged_ < kLogInterval) {
            return;  // reported with the next, or at exit
        }
        last_logged_ = now;
        count = std::exchange(lost_unlogged_, 0);
    }
    log_->error(
        "capture log: {} ({} line(s) lost since the last report; the captures stay "
        "listed from memory, see status)",
        message, count);
}

void CaptureWorker::report_lost(bool at_exit) {
    std::uint64_t count = 0;
    std::string error;
    {
        const std::lock_guard lock(mutex_);
        const auto now = Clock::now();
        if (lost_unlogged_ == 0 ||
            (!at_exit && last_logged_ && now - *last_logged_ < kLogInterval)) {
            return;
        }
        last_logged_ = now;
        count = std::exchange(lost_unlogged_, 0);
        error = stats_.error.value_or("none now");
    }
    log_->error("capture log: {} line(s) lost since the last report (error: {})", count, error);
}

}  // namespace gport::capture
