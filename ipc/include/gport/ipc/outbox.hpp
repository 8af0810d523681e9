// One client's bounded outbound queue of whole lines (docs/api.md, "Slow
// clients": slow clients never slow anyone else, memory stays bounded).
//
// - Replies and link/motion notifications must not be lost: when the queue
//   is full, the oldest queued attitude line is dropped to make room; if
//   there is none, push() fails and the caller disconnects the client.
// - Attitude lines are the ones dropped: when full, the oldest queued
//   attitude goes so the newest is kept (or, with no attitude queued, the
//   new one is dropped). Drops are counted, and the next attitude line queued
//   after a drop carries "dropped":<count so far> for this client.
// - take() moves lines out for one write; the writer holds them until the
//   write completes, so lines are never split or interleaved.
// - A reply that carries descriptors (attitude_channel) is written on its
//   own: take() stops before it, and the writer sends it with sendmsg once it
//   is at the front (front_descriptors(), pop_front()).
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <vector>

#include "gport/ipc/event_json.hpp"

namespace gport::ipc {

class Outbox {
  public:
    static constexpr std::size_t kDefaultByteLimit = 256 * 1024;

    // `line_limit`: lines queued; `byte_limit`: their total size.
    explicit Outbox(std::size_t line_limit, std::size_t byte_limit = kDefaultByteLimit);

    // A reply or a link/motion notification, with the number of attitude
    // channel descriptors that go with its first byte. False: it cannot be
    // queued.
    [[nodiscard]] bool push(Line line, std::size_t descriptors = 0);
    // An attitude notification; returns how many attitude lines were dropped.
    std::size_t push_attitude(const AttitudeLine& line);
    // An attitude notification not queued (the server is short of memory):
    // counted and reported like any other drop; returns 1.
    std::size_t drop_attitude();

    // Moves up to `max_lines` queued lines (oldest first) to the end of `out`,
    // stopping before a line that carries descriptors.
    void take(std::vector<Line>& out, std::size_t max_lines);
    // The descriptors the front line carries (0 for most lines).
    std::size_t front_descriptors() const;
    // The front line itself. The queue must not be empty.
    const Line& front() const { return queue_.front().line; }
    // Removes the front line and returns it. The queue must not be empty.
    Line pop_front();
    // Puts `line`, without descriptors, in the front line's place (a reply
    // whose descriptors could not be sent). The queue must not be empty.
    void replace_front(Line line);

    bool empty() const { return queue_.empty(); }
    std::size_t size() const { return queue_.size(); }
    std::size_t bytes() const { return bytes_; }
    // Bytes of replies and link/motion lines: what back-pressure looks at.
    std::size_t reply_bytes() const { return bytes_ - attitude_bytes_; }
    std::uint64_t dropped() const { return dropped_; }

  private:
    struct Entry {
        Line line;
        bool attitude = false;
        std::size_t descriptors = 0;
    };

    bool fits(std::size_t size) const;
    bool drop_oldest_attitude();
    void append(Line line, bool attitude, std::size_t descriptors = 0);

    std::deque<Entry> queue_;
    std::size_t line_limit_;
    std::size_t byte_limit_;
    std::size_t bytes_ = 0;
    std::size_t attitude_bytes_ = 0;
    std::uint64_t dropped_ = 0;
    bool report_drops_ = false;  // the next attitude line carries the count
};

}  // namespace gport::ipc
