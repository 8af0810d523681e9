// gport-mavlink's repeated log lines, limited per kind (log_limit.hpp's
// KindLimiter): the first of a kind (or the first few, `per_window`) in a
// minute are written with their details, the next ones are counted, and a
// summary line gives the count. The text is made only when it is written:
// a flood costs a lookup per frame, not a formatted string.
#pragma once

#include <spdlog/spdlog.h>

#include <chrono>
#include <concepts>
#include <cstdint>
#include <string>
#include <string_view>

#include "gport/mavlink/bridge/log_limit.hpp"
#include "gport/mavlink/messages.hpp"

namespace gport::mavlink::bridge {

// A frame's message name for log lines: "GIMBAL_DEVICE_SET_ATTITUDE", or
// "message 1234" for one the codec does not know.
inline std::string message_name(std::uint32_t msgid) {
    const MessageInfo* info = find_message(msgid);
    return info != nullptr ? std::string(info->name) : "message " + std::to_string(msgid);
}

class Logbook {
  public:
    explicit Logbook(std::chrono::milliseconds window = std::chrono::seconds(60))
        : limiter_(window) {}

    // A line of `kind` (fixed words) at `level`; `text()` makes it, called
    // only when the line is written (one of the first `per_window` of its
    // kind in a window).
    template <std::invocable Text>
    void note(spdlog::level::level_enum level, std::string_view kind, Text&& text,
              std::uint32_t per_window = 1) {
        if (limiter_.admit(kind, KindLimiter::Clock::now(), per_window)) {
            spdlog::log(level, "{}", std::string(text()));
        }
    }
    template <std::invocable Text>
    void warn(std::string_view kind, Text&& text) {
        note(spdlog::level::warn, kind, std::forward<Text>(text));
    }
    void warn(std::string_view kind, const std::string& text) {
        note(spdlog::level::warn, kind, [&text] { return text; });
    }

    // The summaries of the windows that ended (call about once a second).
    void tick() { write(limiter_.expire(KindLimiter::Clock::now())); }

    // Every pending summary (at exit).
    void flush() { write(limiter_.flush(KindLimiter::Clock::now())); }

  private:
    static void write(const std::vector<KindLimiter::Summary>& summaries) {
        for (const auto& s : summaries) {
            spdlog::warn(
                "{}: {} more in the last {:.1f} s (repeats are counted, written once a minute)",
                s.kind, s.suppressed, std::chrono::duration<double>(s.over).count());
        }
    }

    KindLimiter limiter_;
};

}  // namespace gport::mavlink::bridge
