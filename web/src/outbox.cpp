#include "gport/web/outbox.hpp"

#include <utility>

#include "gport/web/limits.hpp"

namespace gport::web {

void Outbox::push(Message message, bool attitude) {
    if (attitude) {
        dropped_ += attitude_ ? 1 : 0;
        attitude_ = std::move(message);
        return;
    }
    if (others_.size() >= kMaxQueuedMessages) {
        others_.pop_front();
        ++dropped_;
    }
    others_.push_back(std::move(message));
}

Message Outbox::pop() {
    if (!others_.empty()) {
        auto message = std::move(others_.front());
        others_.pop_front();
        return message;
    }
    return std::exchange(attitude_, nullptr);
}

}  // namespace gport::web
