// Keeping gport-mavlink's log bounded whatever the network sends: pure
// bookkeeping (time is passed in), the Bridge writes the lines.
//
// KindLimiter: repeated lines are limited per KIND (a fixed text such as
// "GIMBAL_DEVICE_SET_ATTITUDE ignored: bad quaternion"), never per value.
// The first `per_window` of a kind (1 unless asked: events worth naming one
// by one, such as reply-peer changes, ask for a few) are written at once,
// with their details; the next ones within `window` are only counted; when
// the window ends, one summary line gives the count, and a new window
// starts while they keep coming (its summary line counts as one of the
// new window's lines). A kind that stays quiet for a whole window is
// forgotten, so its next occurrence is written at once again. There is no
// lifetime cap: every window names its first occurrences and counts the
// rest. Memory: one entry per kind, at most `max_kinds` (kinds are the
// program's fixed texts; past the cap, new kinds share one entry,
// "other").
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace gport::mavlink::bridge {

class KindLimiter {
  public:
    using Clock = std::chrono::steady_clock;

    struct Summary {
        std::string kind;
        std::uint64_t suppressed = 0;       // lines not written
        std::chrono::milliseconds over{0};  // since the window began
    };

    explicit KindLimiter(std::chrono::milliseconds window = std::chrono::seconds(60),
                         std::size_t max_kinds = 64);

    // True when a line of this kind is to be written now (one of the first
    // `per_window` in its window); false when it is only counted.
    bool admit(std::string_view kind, Clock::time_point now, std::uint32_t per_window = 1);

    // The summaries of the windows that have ended by `now` (kinds with
    // nothing suppressed are forgotten, without a summary).
    std::vector<Summary> expire(Clock::time_point now);

    // Every pending summary, at exit.
    std::vector<Summary> flush(Clock::time_point now);

    std::size_t kinds() const { return entries_.size(); }

  private:
    struct Entry {
        std::string kind;
        Clock::time_point window_start;
        std::uint32_t written = 0;  // lines of this window, its summary included
        std::uint64_t suppressed = 0;
    };

    std::chrono::milliseconds window_;
    std::size_t max_kinds_;
    std::vector<Entry> entries_;
};

}  // namespace gport::mavlink::bridge
