// The capture log's memory (docs/api.md, "Captures"): every photo and record
// toggle that reached the wire, as the `captures` method lists it. It gives
// each capture its index (monotonic, never reused: the last one and a durable
// high-water mark are restored from disk, capture_writer.hpp), keeps the
// newest as the text it serves, tells a listener (ipc's `capture` topic) and
// hands the line to a sink (CaptureWriter's thread, which owns every disk
// access). Pure: no I/O here.
//
// A capture is made in two steps, so that a request either sends its frame
// and records it, or does neither: prepare() builds the line (any invalid
// UTF-8 replaced) and checks an index can be given, before the frame is sent;
// add() gives the index and keeps it, after.
//
// Single-threaded: every call is on gportd's event loop.
// The sink's write() must not block (it queues).
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace gport::capture {

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
    static constexpr std::size_t kKept = 4096;           // captures listed, newest kept
    static constexpr std::size_t kKeptBytes = 8u << 20;  // ... and at most this much text
    static constexpr std::size_t kMetaMaxBytes = 1024;   // `meta`, compactly serialized
    static constexpr std::size_t kMaxLimit = 1000;       // captures per `captures` reply
    static constexpr std::size_t kDefaultLimit = 100;
    // A `captures` page holds at most this much text (and at least one
    // capture), far below a client's output limit (socket.queue_limit lines,
    // 256 KiB): a page always fits, whatever the metas.
    static constexpr std::size_t kMaxPageBytes = 64u << 10;
    // Indexes stay JSON-safe integers (exact in a double): 2^53 - 1.
    static constexpr std::uint64_t kMaxIndex = (std::uint64_t{1} << 53) - 1;
    // Indexes reserved ahead of the durable mark, and how close to it the
    // next reservation is asked for.
    static constexpr std::uint64_t kReserveAhead = 1000;
    static constexpr std::uint64_t kReserveWhenWithin = 500;

    // A capture built but not yet given an index (prepare()).
    struct Prepared {
        std::string body;  // the capture's members, serialized, without braces
        // Adds a member known only once the frame is sent (its moment).
        void append(std::string_view key, const nlohmann::json& value);
    };

    explicit CaptureLog(std::size_t kept = kKept) : kept_(kept) {}

    // Captures read back at start (JSON lines in any order; a line that is
    // not a capture object with an index in 1..kMaxIndex, or is nested too
    // deep, is skipped; duplicates are kept once), and the index to give
    // next (at least one past the highest restored). Before any add().
    void restore(const std::vector<std::string>& lines, std::uint64_t next_index);
    // nullptr: kept in memory only.
    void set_sink(CaptureSink* sink) { sink_ = sink; }
    // Called with each capture added, as its JSON text (the `capture`
    // notification's params).
    void on_added(std::function<void(std::string_view capture)> listener) {
        listener_ = std::move(listener);
    }

    // Builds the capture's text, or says why no index can be given now.
    // Asks the sink to move the durable mark when the next index is near it
    // (every call near it asks again: a disk that failed may have recovered).
    std::variant<Prepared, std::string> prepare(const nlohmann::json& capture);
    // What add() stored: the index given and the capture's text (valid until
    // the next change to the log).
    struct Stored {
        std::uint64_t index;
        std::string_view text;
    };
    // Gives the prepared capture the next index and its `kind` (both first
    // in the text), keeps it, queues its line and tells the listener.
    Stored add(Prepared prepared, std::string_view kind);

    // {"captures": [those with index >= since, oldest first, at most limit
    //  and at most kMaxPageBytes of them], "more": whether captures at or
    //  after "next" are kept, "next": the index to ask for next}, as text.
    std::string list(std::uint64_t since, std::size_t limit) const;

    // status's "captures": {"added", "next_index", "file", "written",
    // "dropped", "error", "reserved"}.
    nlohmann::json status() const;

    std::uint64_t next_index() const { return next_index_; }

  private:
    struct Kept {
        std::uint64_t index = 0;
        std::string text;
    };
    void keep(std::uint64_t index, std::string text);
    void reserve_ahead();

    std::size_t kept_;
    std::deque<Kept> captures_;
    std::size_t kept_bytes_ = 0;
    std::uint64_t next_index_ = 1;
    std::uint64_t added_ = 0;
    CaptureSink* sink_ = nullptr;
    std::function<void(std::string_view)> listener_;
};

}  // namespace gport::capture
