// One client's attitude rate limit (subscribe's max_rate_hz), as a pure
// decision: no timers, no sockets. It is given the time; it says whether a
// sample goes now or waits, keeps only the newest waiting sample, and says
// when the owner should wake it to send that one.
//
// - A sample goes at once when no wake-up is pending and at least one
//   interval has passed since the last one sent (or none was sent yet).
// - Otherwise it is held, replacing any older held sample (the newest
//   matters), and the first sample held asks for a wake-up one interval
//   after the last one sent. Later samples wait for that same wake-up.
// - At the wake-up the held sample (if any) goes, and the interval counts
//   from then.
#pragma once

#include <chrono>
#include <optional>

#include "gport/ipc/event_json.hpp"

namespace gport::ipc {

class AttitudePacer {
  public:
    using Clock = std::chrono::steady_clock;

    enum class Decision {
        kSend,         // send this sample now
        kHold,         // held; the wake-up already asked for will send it
        kHoldAndWake,  // held; wake at wake_at() and call woken()
    };

    Decision offer(const AttitudeLine& sample, Clock::time_point now, Clock::duration interval);

    // Valid after kHoldAndWake, until woken() or disarmed().
    Clock::time_point wake_at() const { return wake_at_; }

    // The wake-up came: the sample to send now (null when none is held).
    AttitudeLine woken(Clock::time_point now);

    // The wake-up will not come (its timer was cancelled); the held sample,
    // if any, stays held.
    void disarmed() { waking_ = false; }

    // Forgets the held sample (the client is going away).
    void clear() { held_.reset(); }

    bool holding() const { return held_ != nullptr; }
    bool waking() const { return waking_; }

  private:
    std::optional<Clock::time_point> last_sent_;  // empty: the next goes at once
    Clock::time_point wake_at_{};
    AttitudeLine held_;
    bool waking_ = false;
};

}  // namespace gport::ipc
