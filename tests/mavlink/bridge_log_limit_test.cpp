// Bounded logging whatever the network sends (log_limit.hpp): per kind, not
// per value; once per sender or peer, in bounded memory.
#include <gtest/gtest.h>

#include <string>

#include "gport/mavlink/bridge/log_limit.hpp"

namespace gport::mavlink::bridge {
namespace {

using namespace std::chrono_literals;
using Clock = KindLimiter::Clock;

TEST(KindLimiter, AThousandOfAKindMakeOneLineAndOneSummary) {
    KindLimiter limiter(60s);
    const Clock::time_point t0{};
    int written = 0;
    for (int i = 0; i < 1000; ++i) {
        written += limiter.admit("GIMBAL_DEVICE_SET_ATTITUDE ignored: bad quaternion",
                                 t0 + std::chrono::milliseconds(i * 4))
                       ? 1
                       : 0;
    }
    EXPECT_EQ(written, 1);
    EXPECT_TRUE(limiter.expire(t0 + 59s).empty());
    const auto summaries = limiter.expire(t0 + 60s);
    ASSERT_EQ(summaries.size(), 1U);
    EXPECT_EQ(summaries[0].kind, "GIMBAL_DEVICE_SET_ATTITUDE ignored: bad quaternion");
    EXPECT_EQ(summaries[0].suppressed, 999U);
    EXPECT_EQ(summaries[0].over, 60s);
}

TEST(KindLimiter, KindsAreCountedApart) {
    KindLimiter limiter(60s);
    const Clock::time_point t0{};
    EXPECT_TRUE(limiter.admit("a", t0));
    EXPECT_TRUE(limiter.admit("b", t0));
    EXPECT_FALSE(limiter.admit("a", t0 + 1s));
    EXPECT_EQ(limiter.kinds(), 2U);
}

TEST(KindLimiter, AStormGivesOneSummaryPerWindowAQuietKindIsForgotten) {
    KindLimiter limiter(60s);
    const Clock::time_point t0{};
    ASSERT_TRUE(limiter.admit("k", t0));
    limiter.admit("k", t0 + 30s);
    ASSERT_EQ(limiter.expire(t0 + 60s).size(), 1U);  // 1 more
    limiter.admit("k", t0 + 70s);                    // still in the new window: counted
    const auto second = limiter.expire(t0 + 120s);
    ASSERT_EQ(second.size(), 1U);
    EXPECT_EQ(second[0].suppressed, 1U);
    EXPECT_TRUE(limiter.expire(t0 + 180s).empty());  // a quiet window: forgotten
    EXPECT_EQ(limiter.kinds(), 0U);
    EXPECT_TRUE(limiter.admit("k", t0 + 181s));  // written at once again
}

TEST(KindLimiter, FlushGivesThePendingCountsAtExit) {
    KindLimiter limiter(60s);
    const Clock::time_point t0{};
    limiter.admit("k", t0);
    limiter.admit("k", t0 + 1s);
    limiter.admit("quiet", t0);
    const auto out = limiter.flush(t0 + 2s);
    ASSERT_EQ(out.size(), 1U);
    EXPECT_EQ(out[0].kind, "k");
    EXPECT_EQ(out[0].suppressed, 1U);
    EXPECT_EQ(limiter.kinds(), 0U);
}

TEST(KindLimiter, MemoryIsBoundedEvenForEndlesslyNewKinds) {
    KindLimiter limiter(60s, 8);
    const Clock::time_point t0{};
    int written = 0;
    for (int i = 0; i < 10000; ++i) {
        written += limiter.admit("kind " + std::to_string(i), t0) ? 1 : 0;
    }
    EXPECT_LE(limiter.kinds(), 8U);
    EXPECT_EQ(written, 8);  // 7 named kinds, then one "other"
    const auto out = limiter.flush(t0 + 1s);
    ASSERT_EQ(out.size(), 1U);
    EXPECT_EQ(out[0].kind, "other");
    EXPECT_EQ(out[0].suppressed, 10000U - 8U);
}

TEST(FirstSightings, OncePerKeyThenOneOverflowThenSilence) {
    FirstSightings<int> seen(3);
    using S = FirstSightings<int>::Sighting;
    EXPECT_EQ(seen.see(1), S::kNew);
    EXPECT_EQ(seen.see(1), S::kKnown);
    EXPECT_EQ(seen.see(2), S::kNew);
    EXPECT_EQ(seen.see(3), S::kNew);
    EXPECT_EQ(seen.see(4), S::kOverflow);
    for (int i = 5; i < 10000; ++i) {
        EXPECT_EQ(seen.see(i), S::kUncounted);
    }
    EXPECT_EQ(seen.see(2), S::kKnown);
    EXPECT_EQ(seen.listed(), 3U);
    EXPECT_EQ(seen.unlisted(), 9996U);
}

}  // namespace
}  // namespace gport::mavlink::bridge
