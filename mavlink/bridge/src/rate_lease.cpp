#include "gport/mavlink/bridge/rate_lease.hpp"

#include <algorithm>
#include <charconv>

namespace gport::mavlink::bridge {

RateLease::ms RateLease::on_rate(Clock::time_point now) {
    if (last_ && now - *last_ <= ceiling_) {
        intervals_[next_] = now - *last_;
        next_ = (next_ + 1) % kIntervals;
    }
    last_ = now;
    return current();
}

RateLease::ms RateLease::current() const {
    const auto longest = *std::max_element(intervals_.begin(), intervals_.end());
    const auto wanted = std::chrono::duration_cast<ms>(longest * 3 / 2);
    return std::clamp(wanted, std::min(floor_, ceiling_), ceiling_);
}

void RateLease::set_ceiling(ms ceiling) {
    ceiling_ = std::max(ceiling, ms{1});
}

std::optional<std::chrono::milliseconds> max_lease_in(std::string_view message) {
    constexpr std::string_view kBefore = "lease_ms must be an integer from 1 to ";
    const auto at = message.find(kBefore);
    if (at == std::string_view::npos) {
        return std::nullopt;
    }
    const char* first = message.data() + at + kBefore.size();
    const char* last = message.data() + message.size();
    long value = 0;
    const auto [end, error] = std::from_chars(first, last, value);
    if (error != std::errc{} || end == first || value < 1) {
        return std::nullopt;
    }
    return std::chrono::milliseconds(value);
}

}  // namespace gport::mavlink::bridge
