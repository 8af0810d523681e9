// The live sockets, and the fan-out of one shared message to all of them.
#pragma once

#include <map>
#include <memory>

#include "gport/web/outbox.hpp"

namespace gport::web {

// What the hub sends to: a live socket.
class Listener {
  public:
    virtual ~Listener() = default;
    virtual void send(const Message& message, bool attitude) = 0;
};

class Hub {
  public:
    void add(const std::shared_ptr<Listener>& listener) { listeners_[listener.get()] = listener; }
    void remove(const Listener* listener) { listeners_.erase(listener); }
    std::size_t size() const { return listeners_.size(); }

    void broadcast(const Message& message, bool attitude) {
        for (auto it = listeners_.begin(); it != listeners_.end();) {
            if (auto listener = it->second.lock()) {
                listener->send(message, attitude);
                ++it;
            } else {
                it = listeners_.erase(it);
            }
        }
    }

  private:
    std::map<const Listener*, std::weak_ptr<Listener>> listeners_;
};

}  // namespace gport::web
