#include "gport/ipc/attitude_pacer.hpp"

#include <utility>

namespace gport::ipc {

AttitudePacer::Decision AttitudePacer::offer(const AttitudeLine& sample, Clock::time_point now,
                                             Clock::duration interval) {
    if (!waking_ && (!last_sent_ || now - *last_sent_ >= interval)) {
        last_sent_ = now;
        return Decision::kSend;
    }
    held_ = sample;  // the newest replaces any older held one
    if (waking_) {
        return Decision::kHold;
    }
    waking_ = true;
    wake_at_ = *last_sent_ + interval;
    return Decision::kHoldAndWake;
}

AttitudeLine AttitudePacer::woken(Clock::time_point now) {
    waking_ = false;
    if (!held_) {
        return nullptr;
    }
    last_sent_ = now;
    return std::exchange(held_, nullptr);
}

}  // namespace gport::ipc
