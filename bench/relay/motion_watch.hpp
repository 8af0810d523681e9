// A direct client of gportd subscribed to `motion`: counts the speed motions
// gportd itself ended because their lease ran out (`lease_expired`), i.e.
// the zero speed that was gportd's deadman and not a relayed stop.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <thread>

namespace gport::bench::relay {

class MotionWatch {
  public:
    explicit MotionWatch(const std::string& socket);  // throws when gportd does not answer
    ~MotionWatch();
    MotionWatch(const MotionWatch&) = delete;
    MotionWatch& operator=(const MotionWatch&) = delete;

    std::uint64_t lease_endings() const { return lease_endings_.load(); }

  private:
    std::atomic<bool> stop_{false};
    std::atomic<std::uint64_t> lease_endings_{0};
    std::thread thread_;
};

}  // namespace gport::bench::relay
