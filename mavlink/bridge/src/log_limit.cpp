#include "gport/mavlink/bridge/log_limit.hpp"

#include <algorithm>

namespace gport::mavlink::bridge {

namespace {

constexpr std::string_view kOtherKind = "other";

}  // namespace

KindLimiter::KindLimiter(std::chrono::milliseconds window, std::size_t max_kinds)
    : window_(window), max_kinds_(std::max<std::size_t>(max_kinds, 1)) {
    entries_.reserve(max_kinds_);
}

bool KindLimiter::admit(std::string_view kind, Clock::time_point now, std::uint32_t per_window) {
    auto it = std::ranges::find(entries_, kind, &Entry::kind);
    // The last entry is kept for "other": named kinds past the cap share it.
    if (it == entries_.end() && kind != kOtherKind && entries_.size() + 1 >= max_kinds_) {
        kind = kOtherKind;
        it = std::ranges::find(entries_, kind, &Entry::kind);
    }
    if (it != entries_.end()) {
        if (it->kind != kOtherKind && it->written < per_window) {
            ++it->written;
            return true;
        }
        ++it->suppressed;
        return false;
    }
    entries_.push_back({std::string(kind), now, 1, 0});
    return true;
}

std::vector<KindLimiter::Summary> KindLimiter::expire(Clock::time_point now) {
    std::vector<Summary> out;
    for (auto it = entries_.begin(); it != entries_.end();) {
        if (now - it->window_start < window_) {
            ++it;
            continue;
        }
        if (it->suppressed == 0) {
            it = entries_.erase(it);
            continue;
        }
        out.push_back(
            {it->kind, it->suppressed,
             std::chrono::duration_cast<std::chrono::milliseconds>(now - it->window_start)});
        it->window_start = now;
        it->written = 1;  // the summary line
        it->suppressed = 0;
        ++it;
    }
    return out;
}

std::vector<KindLimiter::Summary> KindLimiter::flush(Clock::time_point now) {
    std::vector<Summary> out;
    for (const auto& e : entries_) {
        if (e.suppressed > 0) {
            out.push_back(
                {e.kind, e.suppressed,
                 std::chrono::duration_cast<std::chrono::milliseconds>(now - e.window_start)});
        }
    }
    entries_.clear();
    return out;
}

}  // namespace gport::mavlink::bridge
