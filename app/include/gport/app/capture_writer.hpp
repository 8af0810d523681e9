// The capture log on disk (docs/operations.md, "The capture log"): JSON lines
// in DIR/captures.jsonl, rotated by size to captures.jsonl.1 ... .N-1. Every
// disk access is here, on a writer thread of its own, behind a bounded queue:
// the event loop only queues a line (ipc::CaptureSink::write never blocks).
// When the disk stalls the queue fills and new lines are dropped and counted;
// a write that fails is counted, its error kept for status and logged at
// most once a minute; the next line tries again (the file reopened).
#pragma once

#include <spdlog/logger.h>

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "gport/ipc/capture_log.hpp"

namespace gport::app {

struct CaptureFiles {
    std::string dir;
    std::uint64_t max_file_bytes = 1048576;
    int keep_files = 4;  // captures.jsonl and .1 ... .keep_files-1

    // n = 0: captures.jsonl; n > 0: captures.jsonl.n.
    std::string file(int n) const;
};

// What start-up reads back: the newest `keep_lines` lines of the kept files,
// oldest first, the index to give next (one past the highest found, 1 if
// none) and what could not be read (each a sentence naming the file).
struct RestoredCaptures {
    std::vector<std::string> lines;
    std::uint64_t next_index = 1;
    std::vector<std::string> problems;
};
RestoredCaptures read_captures(const CaptureFiles& files, std::size_t keep_lines);

class CaptureWriter final : public ipc::CaptureSink {
  public:
    static constexpr std::size_t kQueueLimit = 256;

    CaptureWriter(CaptureFiles files, std::shared_ptr<spdlog::logger> log,
                  std::size_t queue_limit = kQueueLimit);
    // Writes what is queued, then joins the thread.
    ~CaptureWriter() override;
    CaptureWriter(const CaptureWriter&) = delete;
    CaptureWriter& operator=(const CaptureWriter&) = delete;

    void write(std::string line) override;
    Stats stats() const override;
    std::string path() const override { return files_.file(0); }

    // Waits until every queued line is written or dropped (tests, benchmarks).
    void drain();

  private:
    void run();
    void write_line(const std::string& line);
    bool open_file();
    void rotate();
    void failed(const std::string& what, int error);

    const CaptureFiles files_;
    std::shared_ptr<spdlog::logger> log_;
    const std::size_t queue_limit_;
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::condition_variable idle_;
    std::deque<std::string> queue_;
    bool busy_ = false;
    bool stopping_ = false;
    Stats stats_;
    // The thread's own: the file and its size, the error log's pace.
    int fd_ = -1;
    std::uint64_t size_ = 0;
    std::uint64_t failures_unlogged_ = 0;
    std::chrono::steady_clock::time_point last_logged_{};
    bool logged_ = false;
    std::thread thread_;
};

}  // namespace gport::app
