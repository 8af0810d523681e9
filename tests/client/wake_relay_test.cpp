// The wake relay moves only forward (review finding 8): a thread that
// loaded an older value of the word and was preempted neither moves the
// relay back nor causes another wake-all.
#include "wake_relay.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <thread>
#include <vector>

namespace gport::testing {
namespace {

using gport::client::WakeRelay;

TEST(WakeRelay, AStaleValueNeitherWakesNorMovesTheRelayBack) {
    WakeRelay relay(10);
    EXPECT_FALSE(relay.claim(10));  // nothing new
    EXPECT_TRUE(relay.claim(12));
    EXPECT_FALSE(relay.claim(11));  // before: relayed (back to 11) ...
    EXPECT_FALSE(relay.claim(12));  // ... and 12 woke everyone a second time
    EXPECT_TRUE(relay.claim(13));
}

TEST(WakeRelay, TheWordWrapsAround) {
    WakeRelay relay(0xffffffffU);
    EXPECT_TRUE(relay.claim(0));
    EXPECT_FALSE(relay.claim(0xffffffffU));
    EXPECT_TRUE(relay.claim(1));
}

// Oversubscribed threads replaying old values: one wake-all per new value.
TEST(WakeRelay, ManyThreadsWithOldValuesWakeOncePerValue) {
    constexpr std::uint32_t kValues = 2000;
    WakeRelay relay(0);
    std::atomic<int> wakes{0};
    std::vector<std::thread> threads;
    for (int t = 0; t < 8; ++t) {
        threads.emplace_back([&, t] {
            for (std::uint32_t v = 1; v <= kValues; ++v) {
                // Each thread lags the newest by a different amount.
                const std::uint32_t seen = v > static_cast<std::uint32_t>(t) ? v - t : v;
                wakes += relay.claim(seen) ? 1 : 0;
            }
        });
    }
    for (auto& thread : threads) {
        thread.join();
    }
    EXPECT_LE(wakes.load(), static_cast<int>(kValues));
    EXPECT_FALSE(relay.claim(kValues));
}

}  // namespace
}  // namespace gport::testing
