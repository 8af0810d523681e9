// The frames waiting for the serial device (not the one being written).
// A stop must never be refused or left behind, and a client must not be able
// to fill memory, so frames are kept by kind:
//  - a stop (0x85 zero speed) goes next, replacing every waiting 0x85; a stop
//    already waiting absorbs it (identical bytes: the wire still ends in a
//    zero speed, and a stop flood on a stuck line costs no memory);
//  - another 0x85 (speed, angle, centre, lock) replaces the waiting non-stop
//    0x85 frame in its place in line (only the newest position command
//    matters, and a keepalive refreshing it never loses its turn), or goes
//    last when none waits;
//  - other frames (camera, settings) are capped; over the cap they are refused.
// At most one stop and one other 0x85 wait, so the queue stays bounded.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>

#include "gport/protocol/frame.hpp"

namespace gport::daemon {

enum class FrameKind { kOther, kMotion, kStop };

class WriteQueue {
  public:
    struct Entry {
        protocol::Frame frame;
        FrameKind kind = FrameKind::kOther;
    };

    explicit WriteQueue(std::size_t max_other) : max_other_(max_other) {}

    // False only for an kOther frame over the cap (counted as refused).
    bool push(const protocol::Frame& frame, FrameKind kind);
    bool empty() const { return entries_.empty(); }
    // The bytes of every waiting frame.
    std::size_t bytes() const;
    Entry pop();
    bool holds_stop() const;
    void clear();

    // Waiting frames dropped because a newer 0x85 took their place.
    std::uint64_t replaced() const { return replaced_; }
    std::uint64_t refused() const { return refused_; }

  private:
    void drop_motion();

    std::deque<Entry> entries_;
    std::size_t max_other_;
    std::size_t others_ = 0;
    std::uint64_t replaced_ = 0;
    std::uint64_t refused_ = 0;
};

}  // namespace gport::daemon
