// The notifications Client keeps for next_notification(): one queue per
// kind (attitude, link, motion) of at most kNotificationQueueLimit each, so
// that a flood of one kind never pushes out another, and at most
// kQueueBytes in all (a server cannot fill it with long strings). When
// full, the oldest (of that kind; by the byte bound, of all) is dropped and
// counted. Taken in arrival order across the kinds.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <optional>
#include <utility>
#include <variant>

#include "gport/client/limits.hpp"
#include "gport/client/types.hpp"

namespace gport::client::detail {

class NotificationQueue {
  public:
    static constexpr std::size_t kQueueBytes = kLineLimit;

    void push(Notification n);
    std::optional<Notification> pop();
    bool empty() const noexcept { return size_ == 0; }
    std::size_t size() const noexcept { return size_; }
    // Notifications dropped since the queue was made.
    std::uint64_t dropped() const noexcept { return dropped_; }

  private:
    using Entry = std::pair<std::uint64_t, Notification>;  // arrival number, item
    static constexpr std::size_t kKinds = std::variant_size_v<Notification>;

    // The kind whose front arrived first; kKinds when empty.
    std::size_t oldest_kind() const noexcept;
    Notification take(std::size_t kind);

    std::array<std::deque<Entry>, kKinds> queues_;
    std::uint64_t arrivals_ = 0;
    std::size_t size_ = 0;
    std::size_t bytes_ = 0;
    std::uint64_t dropped_ = 0;
};

}  // namespace gport::client::detail
