// One live socket's outbound queue: at most one attitude (the newest
// replaces the older) and at most kMaxQueuedMessages others (the oldest
// dropped and counted), so that a browser that stops reading costs a
// bounded amount of memory. Messages are shared: one string per
// notification, whatever the number of sockets.
#pragma once

#include <cstddef>
#include <deque>
#include <memory>
#include <string>

namespace gport::web {

using Message = std::shared_ptr<const std::string>;

class Outbox {
  public:
    void push(Message message, bool attitude);
    // The next message to write (others before the attitude), or null.
    Message pop();
    bool empty() const { return !attitude_ && others_.empty(); }
    std::size_t size() const { return others_.size() + (attitude_ ? 1 : 0); }
    std::size_t dropped() const { return dropped_; }

  private:
    Message attitude_;
    std::deque<Message> others_;
    std::size_t dropped_ = 0;
};

}  // namespace gport::web
