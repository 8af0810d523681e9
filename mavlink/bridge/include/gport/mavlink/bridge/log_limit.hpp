// Keeping gport-mavlink's log bounded whatever the network sends: pure
// bookkeeping (time is passed in), the Bridge writes the lines.
//
// KindLimiter: repeated warnings are limited per KIND (a fixed text such as
// "GIMBAL_DEVICE_SET_ATTITUDE ignored: bad quaternion"), never per value.
// The first of a kind is written at once, with its details; the next ones
// within `window` are only counted; when the window ends, one summary line
// gives the count (and a new window starts while they keep coming). A kind
// that stays quiet for a whole window is forgotten, so its next occurrence
// is written at once again. Memory: one entry per kind, at most
// `max_kinds` (kinds are the program's fixed texts; past the cap, new kinds
// share one entry, "other").
//
// FirstSightings: "once per sender" and "once per new peer" with bounded
// memory: the first `capacity` distinct keys are reported once each; after
// that one overflow report, then nothing (the keys are only counted).
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

    // True when a line of this kind is to be written now; false when it is
    // only counted.
    bool admit(std::string_view kind, Clock::time_point now);

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
        std::uint64_t suppressed = 0;
    };

    std::chrono::milliseconds window_;
    std::size_t max_kinds_;
    std::vector<Entry> entries_;
};

template <typename Key>
class FirstSightings {
  public:
    enum class Sighting {
        kNew,       // first time: report it
        kKnown,     // seen before: say nothing
        kOverflow,  // the table just filled up: report that, once
        kUncounted  // after the overflow: say nothing
    };

    explicit FirstSightings(std::size_t capacity) : capacity_(capacity) { keys_.reserve(capacity); }

    Sighting see(const Key& key) {
        for (const auto& k : keys_) {
            if (k == key) {
                return Sighting::kKnown;
            }
        }
        if (keys_.size() < capacity_) {
            keys_.push_back(key);
            return Sighting::kNew;
        }
        ++unlisted_;
        return unlisted_ == 1 ? Sighting::kOverflow : Sighting::kUncounted;
    }

    std::size_t listed() const { return keys_.size(); }
    // Sightings of keys that did not fit (each counted, even repeats).
    std::uint64_t unlisted() const { return unlisted_; }
    std::size_t capacity() const { return capacity_; }

  private:
    std::size_t capacity_;
    std::vector<Key> keys_;
    std::uint64_t unlisted_ = 0;
};

}  // namespace gport::mavlink::bridge
