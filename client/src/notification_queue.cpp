#include "notification_queue.hpp"

#include <string>

namespace gport::client::detail {
namespace {

// What a notification holds in memory, its strings' buffers included.
std::size_t footprint(const Notification& n) {
    std::size_t heap = 0;
    if (const auto* link = std::get_if<LinkEvent>(&n)) {
        heap = link->state.capacity() + link->reason.capacity();
    } else if (const auto* motion = std::get_if<MotionEvent>(&n)) {
        heap = motion->change.capacity() + motion->mode.capacity() +
               (motion->reason ? motion->reason->capacity() : 0);
        for (const auto& axis : motion->braked) {
            heap += sizeof(std::string) + axis.capacity();
        }
    }
    return sizeof(std::pair<std::uint64_t, Notification>) + heap;
}

}  // namespace

void NotificationQueue::push(Notification n) {
    const std::size_t kind = n.index();
    if (queues_[kind].size() >= kNotificationQueueLimit) {
        take(kind);
        ++dropped_;
    }
    bytes_ += footprint(n);
    queues_[kind].emplace_back(++arrivals_, std::move(n));
    ++size_;
    while (bytes_ > kQueueBytes && size_ > 1) {
        take(oldest_kind());
        ++dropped_;
    }
}

std::optional<Notification> NotificationQueue::pop() {
    const std::size_t kind = oldest_kind();
    if (kind == kKinds) {
        return std::nullopt;
    }
    return take(kind);
}

std::size_t NotificationQueue::oldest_kind() const noexcept {
    std::size_t best = kKinds;
    for (std::size_t k = 0; k < kKinds; ++k) {
        if (!queues_[k].empty() &&
            (best == kKinds || queues_[k].front().first < queues_[best].front().first)) {
            best = k;
        }
    }
    return best;
}

Notification NotificationQueue::take(std::size_t kind) {
    auto n = std::move(queues_[kind].front().second);
    queues_[kind].pop_front();
    bytes_ -= footprint(n);
    --size_;
    return n;
}

}  // namespace gport::client::detail
