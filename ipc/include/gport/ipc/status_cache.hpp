// The part of the `status` result that is the same for every caller, kept
// serialized and rebuilt at most every kMaxAge, so that clients polling
// `status` back to back cost the loop a string copy each instead of a full
// JSON build (docs/api.md, "status"; docs/performance.md, "Fairness").
//
// Staleness: the shared members may be up to max_age old. The server
// invalidates the cache whenever something a caller could have caused or
// be waiting for changes (any request other than status, a link or motion
// event, a client connecting or leaving), so only the figures that move on
// their own (uptime_ms, attitude_age_ms, the counters) lag, by at most
// max_age. The caller's own `client` member is never cached: it is built
// for each request.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>

namespace gport::ipc {

class StatusCache {
  public:
    using Clock = std::chrono::steady_clock;
    static constexpr std::chrono::milliseconds kMaxAge{5};

    explicit StatusCache(Clock::duration max_age = kMaxAge) : max_age_(max_age) {}

    // The shared members, serialized without the object's braces
    // ("\"api_version\":1,..."): the cached text while it is younger than
    // max_age and valid, else what `build` returns now (then kept).
    const std::string& members(Clock::time_point now, const std::function<std::string()>& build);

    // The next members() call rebuilds.
    void invalidate() { valid_ = false; }
    // How many times the members were built (for tests and the benchmark).
    std::uint64_t builds() const { return builds_; }

  private:
    Clock::duration max_age_;
    Clock::time_point built_{};
    std::string text_;
    bool valid_ = false;
    std::uint64_t builds_ = 0;
};

}  // namespace gport::ipc
