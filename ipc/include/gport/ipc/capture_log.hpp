// The capture log's memory (docs/api.md, "Captures"): every photo and record
// toggle that reached the wire, as the `captures` method lists it. It gives
// each capture its index (monotonic; app/ restores the last one from disk, so
// indexes are never reused across restarts), keeps the newest kKept, tells a
// listener (the server's `capture` topic) and hands the line to a sink
// (app/'s writer thread, which owns every disk access). Pure: no I/O here.
//
// Single-threaded, like the rest of ipc: every call is on the loop's thread.
// The sink's write() must not block (it queues).
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace gport::ipc {

// Where the lines go to be persisted.
class CaptureSink {
  public:
    struct Stats {
        std::uint64_t written = 0;         // lines written to the file
        std::uint64_t dropped = 0;         // lines lost: queue full or a write that failed
        std::optional<std::string> error;  // the last write error, until a write succeeds
    };
    virtual ~CaptureSink() = default;
    // Queues one JSON line (no '\n'); never blocks.
    virtual void write(std::string line) = 0;
    // Asks for the high-water mark `upto` to be made durable: after a
    // restart no index below it is given again. Never blocks (the writer
    // persists it); marks only grow.
    virtual void reserve(std::uint64_t /*upto*/) {}
    // The highest mark known to be durable; nullopt when the log has no
    // durable storage (its indexes are then per-run, as status says; the
    // default, for sinks that keep nothing).
    virtual std::optional<std::uint64_t> reserved() const { return std::nullopt; }
    virtual Stats stats() const = 0;
    // The file written, for status ("" when none).
    virtual std::string path() const = 0;
};

class CaptureLog {
  public:
    static constexpr std::size_t kKept = 4096;          // captures listed, newest kept
    static constexpr std::size_t kMetaMaxBytes = 1024;  // `meta`, compactly serialized
    static constexpr std::size_t kMaxLimit = 1000;      // captures per `captures` reply
    static constexpr std::size_t kDefaultLimit = 100;

    explicit CaptureLog(std::size_t kept = kKept) : kept_(kept) {}

    // Captures read back at start, oldest first (JSON lines; a line that is
    // not a capture object with an index is skipped), and the index to give
    // next (at least one past the highest restored). Before any add().
    void restore(const std::vector<std::string>& lines, std::uint64_t next_index);
    // nullptr: kept in memory only.
    void set_sink(CaptureSink* sink) { sink_ = sink; }
    // Called with each capture added (the `capture` notification).
    void on_added(std::function<void(const nlohmann::json&)> listener) {
        listener_ = std::move(listener);
    }

    // Gives `capture` the next index (member "index", first), keeps it,
    // queues its line and tells the listener. Returns the stored capture.
    const nlohmann::json& add(nlohmann::json capture);

    // {"captures": [those with index >= since, oldest first, at most limit],
    //  "next": the index to ask for next}.
    nlohmann::json list(std::uint64_t since, std::size_t limit) const;

    // status's "captures": {"written", "dropped", "error", "file", "next_index"}.
    nlohmann::json status() const;

    std::uint64_t next_index() const { return next_index_; }

  private:
    void keep(nlohmann::json capture);

    std::size_t kept_;
    std::deque<nlohmann::json> captures_;
    std::uint64_t next_index_ = 1;
    std::uint64_t added_ = 0;
    CaptureSink* sink_ = nullptr;
    std::function<void(const nlohmann::json&)> listener_;
};

}  // namespace gport::ipc
