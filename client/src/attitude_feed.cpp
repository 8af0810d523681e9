// AttitudeFeed: a channel and the waiter thread that makes its wakes pollable.
#include "attitude_feed.hpp"

#include <utility>

#include "gport/client/error.hpp"
#include "ring_channel.hpp"

namespace gport::client {

AttitudeFeed::AttitudeFeed(AttitudeChannel channel) : channel_(std::move(channel)) {
    if (channel_.impl() == nullptr) {
        throw Error(ErrorCode::kBadReply, "attitude channel: an empty channel cannot be fed");
    }
    channel_.impl()->skip_to_newest();
    waker_ = std::make_unique<RingWaker>(channel_.impl()->mapping);
}

AttitudeFeed::~AttitudeFeed() = default;

int AttitudeFeed::fd() const noexcept {
    return waker_->fd();
}

void AttitudeFeed::reset() noexcept {
    waker_->reset();
}

std::optional<AttitudeSample> AttitudeFeed::take() {
    return channel_.impl()->take();
}

}  // namespace gport::client
