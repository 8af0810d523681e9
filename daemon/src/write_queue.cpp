#include "gport/daemon/core/write_queue.hpp"

#include <algorithm>

namespace gport::daemon {

bool WriteQueue::push(const protocol::Frame& frame, FrameKind kind) {
    switch (kind) {
        case FrameKind::kStop:
            drop_motion();
            // A waiting stop is always at the front: only stops go there.
            if (!entries_.empty() && entries_.front().kind == FrameKind::kStop) {
                ++replaced_;
                return true;
            }
            entries_.push_front(Entry{frame, kind});
            return true;
        case FrameKind::kMotion: {
            // The newest replaces the waiting one in its place in line: a
            // keepalive refreshing a speed behind a queue of camera frames
            // must not go back to the end each time (it would never be sent).
            const auto waiting = std::find_if(entries_.begin(), entries_.end(), [](const Entry& e) {
                return e.kind == FrameKind::kMotion;
            });
            if (waiting != entries_.end()) {
                waiting->frame = frame;
                ++replaced_;
                return true;
            }
            entries_.push_back(Entry{frame, kind});
            return true;
        }
        case FrameKind::kOther:
            if (others_ >= max_other_) {
                ++refused_;
                return false;
            }
            ++others_;
            entries_.push_back(Entry{frame, kind});
            return true;
    }
    return false;
}

WriteQueue::Entry WriteQueue::pop() {
    Entry e = entries_.front();
    entries_.pop_front();
    if (e.kind == FrameKind::kOther) {
        --others_;
    }
    return e;
}

std::size_t WriteQueue::bytes() const {
    std::size_t total = 0;
    for (const auto& entry : entries_) {
        total += entry.frame.bytes().size();
    }
    return total;
}

bool WriteQueue::holds_stop() const {
    return !entries_.empty() && entries_.front().kind == FrameKind::kStop;
}

void WriteQueue::clear() {
    entries_.clear();
    others_ = 0;
}

void WriteQueue::drop_motion() {
    const auto n =
        std::erase_if(entries_, [](const Entry& e) { return e.kind == FrameKind::kMotion; });
    replaced_ += n;
}

}  // namespace gport::daemon
