// A token bucket: `rate` tokens a second, holding at most `burst`, full when
// made. take() spends tokens only when they are there; charge() spends them
// regardless (a cost known only afterwards), down to a debt of one burst, so
// a costly caller waits for the bucket to refill before its next take().
//
// Standard C++20, no I/O; the caller passes the time, so tests drive it.
#pragma once

#include <algorithm>
#include <chrono>

namespace gport::base {

class TokenBucket {
  public:
    using Clock = std::chrono::steady_clock;

    TokenBucket(double rate, double burst) : rate_(rate), burst_(burst), tokens_(burst) {}

    double rate() const { return rate_; }
    double burst() const { return burst_; }

    // Spends n tokens if the bucket holds them.
    bool take(Clock::time_point now, double n = 1) {
        refill(now);
        if (tokens_ < n) {
            return false;
        }
        tokens_ -= n;
        return true;
    }

    // Spends n tokens even when fewer are there (down to -burst).
    void charge(Clock::time_point now, double n) {
        refill(now);
        tokens_ = std::max(tokens_ - n, -burst_);
    }

    // How long until n tokens (at most one burst) are there; zero if now.
    Clock::duration wait_for(Clock::time_point now, double n = 1) const {
        const double have = level(now);
        const double missing = std::min(n, burst_) - have;
        if (missing <= 0 || rate_ <= 0) {
            return Clock::duration::zero();
        }
        return std::chrono::ceil<Clock::duration>(std::chrono::duration<double>(missing / rate_));
    }

    // The tokens there at `now`.
    double level(Clock::time_point now) const {
        if (!started_) {
            return tokens_;
        }
        const double elapsed = std::chrono::duration<double>(now - last_).count();
        return std::min(burst_, tokens_ + std::max(elapsed, 0.0) * rate_);
    }

  private:
    void refill(Clock::time_point now) {
        tokens_ = level(now);
        last_ = now;
        started_ = true;
    }

    double rate_;
    double burst_;
    double tokens_;
    Clock::time_point last_{};
    bool started_ = false;
};

}  // namespace gport::base
