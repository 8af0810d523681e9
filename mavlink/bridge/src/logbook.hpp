// gport-mavlink's warnings, limited per kind (log_limit.hpp's KindLimiter):
// the first of a kind is written with its details, the next ones within a
// minute are counted, and a summary line gives the count.
#pragma once

#include <spdlog/spdlog.h>

#include <chrono>
#include <string>
#include <string_view>

#include "gport/mavlink/bridge/log_limit.hpp"

namespace gport::mavlink::bridge {

class Logbook {
  public:
    explicit Logbook(std::chrono::milliseconds window = std::chrono::seconds(60))
        : limiter_(window) {}

    // A warning of `kind` (fixed words); `text` is written when it is the
    // first of its kind in a window.
    void warn(std::string_view kind, const std::string& text) {
        if (limiter_.admit(kind, KindLimiter::Clock::now())) {
            spdlog::warn("{}", text);
        }
    }

    // The summaries of the windows that ended (call about once a second).
    void tick() { write(limiter_.expire(KindLimiter::Clock::now())); }

    // Every pending summary (at exit).
    void flush() { write(limiter_.flush(KindLimiter::Clock::now())); }

  private:
    static void write(const std::vector<KindLimiter::Summary>& summaries) {
        for (const auto& s : summaries) {
            spdlog::warn(
                "{}: {} more in the last {:.1f} s (repeats of a warning are counted, "
                "written once a minute)",
                s.kind, s.suppressed, std::chrono::duration<double>(s.over).count());
        }
    }

    KindLimiter limiter_;
};

}  // namespace gport::mavlink::bridge
