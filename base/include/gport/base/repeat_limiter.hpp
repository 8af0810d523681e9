// Keeps a repeated fault from flooding the journal: the first occurrence is
// reported at once, later ones at most once per interval as a summary that
// says how many were suppressed.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>

namespace gport::base {

class RepeatLimiter {
  public:
    using Clock = std::chrono::steady_clock;

    explicit RepeatLimiter(Clock::duration interval) : interval_(interval) {}

    // Records one occurrence. Returns the number of occurrences since the last
    // report (including this one) when this one should be reported, or empty
    // when it should be suppressed.
    std::optional<std::uint64_t> occur(Clock::time_point now = Clock::now()) {
        ++pending_;
        if (reported_ && now - last_report_ < interval_) {
            return std::nullopt;
        }
        reported_ = true;
        last_report_ = now;
        const auto count = pending_;
        pending_ = 0;
        return count;
    }

    // Forget the series (the fault cleared): the next one is reported at once.
    void reset() {
        reported_ = false;
        pending_ = 0;
    }

  private:
    Clock::duration interval_;
    Clock::time_point last_report_{};
    std::uint64_t pending_ = 0;
    bool reported_ = false;
};

}  // namespace gport::base
