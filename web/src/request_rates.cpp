#include "gport/web/request_rates.hpp"

#include <cmath>

#include "gport/web/limits.hpp"

namespace gport::web {

std::optional<int> RequestRates::take(const std::string& address, Clock::time_point now) {
    auto it = buckets_.find(address);
    if (it == buckets_.end()) {
        if (buckets_.size() >= kMaxRateAddresses) {
            buckets_.erase(order_.front());
            order_.pop_front();
        }
        order_.push_back(address);
        it = buckets_
                 .emplace(address, Entry{base::TokenBucket(kApiRequestsPerSecond, kApiRequestBurst),
                                         std::prev(order_.end())})
                 .first;
    } else {
        order_.splice(order_.end(), order_, it->second.order);
    }
    auto& bucket = it->second.bucket;
    if (bucket.take(now)) {
        return std::nullopt;
    }
    const auto wait = std::chrono::duration<double>(bucket.wait_for(now)).count();
    return std::max(1, static_cast<int>(std::ceil(wait)));
}

}  // namespace gport::web
