#include "gport/app/capture_writer.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <deque>
#include <fstream>
#include <nlohmann/json.hpp>

namespace gport::app {
namespace {

constexpr auto kErrorLogInterval = std::chrono::minutes(1);

}  // namespace

std::string CaptureFiles::file(int n) const {
    return n == 0 ? dir + "/captures.jsonl" : fmt::format("{}/captures.jsonl.{}", dir, n);
}

RestoredCaptures read_captures(const CaptureFiles& files, std::size_t keep_lines) {
    RestoredCaptures out;
    std::deque<std::string> lines;
    for (int n = files.keep_files - 1; n >= 0; --n) {
        const auto path = files.file(n);
        struct stat st {};
        if (::stat(path.c_str(), &st) != 0) {
            if (errno != ENOENT) {
                out.problems.push_back(fmt::format("{}: {}", path, std::strerror(errno)));
            }
            continue;
        }
        if (!S_ISREG(st.st_mode)) {  // a device (/dev/full) or a directory: nothing to read
            out.problems.push_back(fmt::format("{}: not a regular file; not read", path));
            continue;
        }
        std::ifstream in(path);
        if (!in) {
            out.problems.push_back(fmt::format("{}: cannot be read", path));
            continue;
        }
        std::size_t skipped = 0;
        for (std::string line; std::getline(in, line);) {
            auto capture = nlohmann::json::parse(line, nullptr, false);
            const auto index = capture.is_object() ? capture.find("index") : capture.end();
            if (!capture.is_object() || index == capture.end() || !index->is_number_unsigned()) {
                ++skipped;  // a line cut short by a crash or a full disk
                continue;
            }
            out.next_index = std::max(out.next_index, index->get<std::uint64_t>() + 1);
            lines.push_back(std::move(line));
            if (lines.size() > keep_lines) {
                lines.pop_front();
            }
        }
        if (skipped > 0) {
            out.problems.push_back(
                fmt::format("{}: {} line(s) that are not captures skipped", path, skipped));
        }
    }
    out.lines.assign(std::make_move_iterator(lines.begin()), std::make_move_iterator(lines.end()));
    return out;
}

CaptureWriter::CaptureWriter(CaptureFiles files, std::shared_ptr<spdlog::logger> log,
                             std::size_t queue_limit)
    : files_(std::move(files)), log_(std::move(log)), queue_limit_(queue_limit) {
    thread_ = std::thread([this] { run(); });
}

CaptureWriter::~CaptureWriter() {
    {
        const std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_one();
    thread_.join();
    if (fd_ >= 0) {
        ::close(fd_);
    }
}

void CaptureWriter::write(std::string line) {
    {
        const std::lock_guard lock(mutex_);
        if (queue_.size() >= queue_limit_) {
            ++stats_.dropped;  // the disk stalls: the loop never waits for it
            return;
        }
        queue_.push_back(std::move(line));
    }
    wake_.notify_one();
}

ipc::CaptureSink::Stats CaptureWriter::stats() const {
    const std::lock_guard lock(mutex_);
    return stats_;
}

void CaptureWriter::drain() {
    std::unique_lock lock(mutex_);
    idle_.wait(lock, [this] { return queue_.empty() && !busy_; });
}

void CaptureWriter::run() {
    std::unique_lock lock(mutex_);
    for (;;) {
        wake_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
        if (queue_.empty()) {
            return;  // stopping, and everything queued is written
        }
        auto line = std::move(queue_.front());
        queue_.pop_front();
        busy_ = true;
        lock.unlock();
        write_line(line);
        lock.lock();
        busy_ = false;
        if (queue_.empty()) {
            idle_.notify_all();
        }
    }
}

bool CaptureWriter::open_file() {
    const auto path = files_.file(0);
    ::mkdir(files_.dir.c_str(), 0750);  // one level, when --state-dir names a new one
    fd_ = ::open(path.c_str(), O_RDWR | O_APPEND | O_CREAT | O_CLOEXEC, 0640);  // RDWR: pread
    if (fd_ < 0) {
        failed("cannot open " + path, errno);
        return false;
    }
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
    return true;
}

void CaptureWriter::rotate() {
    ::close(fd_);
    fd_ = -1;
    for (int n = files_.keep_files - 1; n >= 1; --n) {
        // The oldest is replaced by the one before it; a missing one is no error.
        std::rename(files_.file(n - 1).c_str(), files_.file(n).c_str());
    }
}

void CaptureWriter::write_line(const std::string& line) {
    if (fd_ >= 0 && size_ > 0 && size_ + line.size() + 1 > files_.max_file_bytes) {
        rotate();
    }
    if (fd_ < 0 && !open_file()) {
        const std::lock_guard lock(mutex_);
        ++stats_.dropped;
        return;
    }
    const std::string text = line + '\n';
    std::size_t done = 0;
    while (done < text.size()) {
        const auto n = ::write(fd_, text.data() + done, text.size() - done);
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n <= 0) {
            failed("cannot write " + files_.file(0), n < 0 ? errno : ENOSPC);
            size_ += done;
            ::close(fd_);
            fd_ = -1;  // reopened (and the cut line ended) for the next capture
            const std::lock_guard lock(mutex_);
            ++stats_.dropped;
            return;
        }
        done += static_cast<std::size_t>(n);
    }
    size_ += done;
    ::fdatasync(fd_);  // on the disk before the next: a drone's power is cut at landing
    const std::lock_guard lock(mutex_);
    ++stats_.written;
    stats_.error.reset();
    logged_ = false;
}

void CaptureWriter::failed(const std::string& what, int error) {
    const auto message = fmt::format("{}: {}", what, std::strerror(error));
    {
        const std::lock_guard lock(mutex_);
        stats_.error = message;
    }
    ++failures_unlogged_;
    const auto now = std::chrono::steady_clock::now();
    if (logged_ && now - last_logged_ < kErrorLogInterval) {
        return;
    }
    log_->error(
        "capture log: {} ({} failure(s) since the last report; captures are kept in "
        "memory, see status)",
        message, failures_unlogged_);
    failures_unlogged_ = 0;
    logged_ = true;
    last_logged_ = now;
}

}  // namespace gport::app
