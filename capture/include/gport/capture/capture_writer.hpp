// The capture log on disk (docs/operations.md, "The capture log"): JSON lines
// in DIR/captures.jsonl, rotated by size to captures.jsonl.1 ... .N-1, and
// the index high-water mark in DIR/captures.next. Every disk access is here:
// start-up reads (read_captures) and a writer thread of its own behind a
// bounded queue (CaptureWriter; CaptureSink::write never blocks).
// Lines are written as they come and fdatasync'd in groups, at most every
// kSyncInterval. Every line lost (queue full, a write that failed, the
// writer abandoned at exit) is counted, its cause kept for status (until a
// line queued after it is written) and logged (at most once a minute, with
// the count).
#pragma once

#include <spdlog/logger.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "gport/capture/capture_log.hpp"

namespace gport::capture {

struct CaptureFiles {
    std::string dir;
    std::uint64_t max_file_bytes = 1048576;
    int keep_files = 4;  // captures.jsonl and .1 ... .keep_files-1

    // n = 0: captures.jsonl; n > 0: captures.jsonl.n.
    std::string file(int n) const;
    // The reservation: the index high-water mark.
    std::string mark() const { return dir + "/captures.next"; }
};

// Indexes kept and given: 1 .. 2^53-1, so that every JSON reader (a double)
// holds them exactly.
inline constexpr std::uint64_t kMaxCaptureIndex = (std::uint64_t{1} << 53) - 1;

// Start-up's limits on what it reads back (a capture line is < 4 KiB: its
// meta is at most 1024 bytes).
inline constexpr std::size_t kMaxCaptureLineBytes = 16384;  // longer lines are skipped
inline constexpr std::size_t kMaxCaptureLineDepth = 64;     // as a request may nest

// What start-up reads back: the newest `keep_lines` captures of the kept
// files sorted by index (a repeated index dropped), the mark stored in
// captures.next, the index to give next (past the highest found and at
// least the stored mark; 1 if neither) and what could not be read or was
// skipped (each a sentence naming the file). Each file is read for at most
// its last max_file_bytes, line by line, a line at most
// kMaxCaptureLineBytes.
struct RestoredCaptures {
    std::vector<std::string> lines;
    std::optional<std::uint64_t> stored_mark;
    std::uint64_t next_index = 1;
    std::vector<std::string> problems;
};
RestoredCaptures read_captures(const CaptureFiles& files, std::size_t keep_lines);

// Creates DIR (one level, 0750) when missing and checks it is gportd's to
// write alone: a directory owned by gportd's uid or root, writable by
// neither its group nor others. nullopt when so; else a sentence naming the
// directory, the fault and the fix.
std::optional<std::string> check_capture_dir(const std::string& dir);

class CaptureWorker;
class CaptureWriter;

// gportd's start-up, before serving: checks DIR, restores `captures` from
// its files and returns the sink to hand it: a CaptureWriter (`writer`), or
// (DIR refused) one that keeps nothing and says why in status. Logs what
// it found. The caller keeps the sink for as long as `captures` uses it.
struct OpenedCaptureLog {
    std::unique_ptr<CaptureSink> sink;
    CaptureWriter* writer = nullptr;
};
OpenedCaptureLog open_capture_log(const CaptureFiles& files, CaptureLog& captures,
                                  const std::shared_ptr<spdlog::logger>& log);

class CaptureWriter final : public CaptureSink {
  public:
    static constexpr std::size_t kQueueLimit = 256;
    // The first mark start-up makes durable: next index + kFirstReservation.
    static constexpr std::uint64_t kFirstReservation = 1000;
    // Lines written are fdatasync'd together, at most this often: a power
    // cut loses at most the lines of the last interval (and those queued).
    static constexpr std::chrono::milliseconds kSyncInterval{100};
    // How long exit waits for the queue before abandoning the thread.
    static constexpr std::chrono::milliseconds kExitWait{2000};

    // Writes `first_mark` to captures.next before returning (start-up, before
    // any capture). When it cannot, the log has no durable storage:
    // reserved() is nullopt, the error logged and kept for status.
    CaptureWriter(CaptureFiles files, std::uint64_t first_mark, std::shared_ptr<spdlog::logger> log,
                  std::size_t queue_limit = kQueueLimit,
                  std::chrono::milliseconds exit_wait = kExitWait);
    // Writes and syncs what is queued, waiting at most exit_wait; then joins
    // the thread, or (a stalled disk) logs the lines not written and leaves
    // the thread behind, holding nothing the process destroys.
    ~CaptureWriter() override;
    CaptureWriter(const CaptureWriter&) = delete;
    CaptureWriter& operator=(const CaptureWriter&) = delete;

    void write(std::string line) override;
    void reserve(std::uint64_t upto) override;
    std::optional<std::uint64_t> reserved() const override;
    Stats stats() const override;
    std::string path() const override { return path_; }

    // A clean stop, after the last capture: the mark becomes `next_index`, so
    // that the next start continues without a gap (after a crash, it skips
    // to the mark).
    void finish(std::uint64_t next_index);

    // Waits until every queued line is written (and synced) or dropped, and
    // every mark asked for is written (tests, benchmarks).
    void drain();

  private:
    std::string path_;
    std::chrono::milliseconds exit_wait_;
    std::shared_ptr<CaptureWorker> worker_;  // shared with the thread
    std::thread thread_;
};

}  // namespace gport::capture
