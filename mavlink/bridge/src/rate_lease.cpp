#include "gport/mavlink/bridge/rate_lease.hpp"

#include <algorithm>
#include <charconv>

namespace gport::mavlink::bridge {

RateLease::ms RateLease::on_message(Clock::time_point now) {
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

client::SpeedOptions speed_options(std::chrono::milliseconds lease) {
    client::SpeedOptions options;
    options.lease = lease;
    options.duration = lease;
    return options;
}

std::optional<std::chrono::milliseconds> max_lease_in(std::string_view message) {
    for (const std::string_view before :
         {"lease_ms must be an integer from 1 to ", "duration_ms must be an integer from 1 to "}) {
        const auto at = message.find(before);
        if (at == std::string_view::npos) {
            continue;
        }
        const char* first = message.data() + at + before.size();
        const char* last = message.data() + message.size();
        long value = 0;
        const auto [end, error] = std::from_chars(first, last, value);
        if (error != std::errc{} || end == first || value < 1) {
            return std::nullopt;
        }
        return std::chrono::milliseconds(value);
    }
    return std::nullopt;
}

}  // namespace gport::mavlink::bridge
