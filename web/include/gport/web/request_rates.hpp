// The API requests each peer address may make (docs/web.md, "Limits"):
// kApiRequestsPerSecond with a burst of kApiRequestBurst, for at most
// kMaxRateAddresses addresses (beyond, those whose bucket is full again
// are forgotten; if none is, the least recently seen). A stop is never
// counted: an open session always stops the gimbal.
#pragma once

#include <chrono>
#include <cstddef>
#include <list>
#include <map>
#include <optional>
#include <string>

#include "gport/base/token_bucket.hpp"

namespace gport::web {

class RequestRates {
  public:
    using Clock = base::TokenBucket::Clock;

    // Takes one request of `address`'s; when it has none left, the seconds
    // until it has one.
    std::optional<int> take(const std::string& address, Clock::time_point now = Clock::now());
    std::size_t addresses() const { return buckets_.size(); }

  private:
    struct Entry {
        base::TokenBucket bucket;
        std::list<std::string>::iterator order;
    };
    std::map<std::string, Entry> buckets_;
    std::list<std::string> order_;  // least recently seen first
};

}  // namespace gport::web
