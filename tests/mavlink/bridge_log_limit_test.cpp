// Bounded logging whatever the network sends (log_limit.hpp): per kind, not
// per value; a few per window for events named one by one; bounded memory.
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

// Reply-peer changes (a local spoofer cycling source ports, issue 22's
// review): a few named per window, the rest counted, every window, forever:
// no lifetime cap after which a takeover goes unlogged.
TEST(KindLimiter, AFewPerWindowNamedTheRestCountedInEveryWindowForever) {
    KindLimiter limiter(60s);
    const Clock::time_point t0{};
    for (int window = 0; window < 100; ++window) {
        const auto start = t0 + window * 60s;
        int written = 0;
        for (int i = 0; i < 25; ++i) {
            written += limiter.admit("peer", start + std::chrono::milliseconds(i), 10) ? 1 : 0;
        }
        // The first window writes 10; later ones 9 (their summary line is the 10th).
        EXPECT_EQ(written, window == 0 ? 10 : 9) << "window " << window;
        const auto summaries = limiter.expire(start + 60s);
        ASSERT_EQ(summaries.size(), 1U) << "window " << window;
        EXPECT_EQ(summaries[0].suppressed, window == 0 ? 15U : 16U);
    }
    EXPECT_TRUE(limiter.expire(t0 + 100 * 60s + 60s).empty());  // quiet: forgotten
    EXPECT_TRUE(limiter.admit("peer", t0 + 102 * 60s, 10));
}

TEST(KindLimiter, PerWindowIsPerKindAndOtherStaysOneLine) {
    KindLimiter limiter(60s, 2);  // one named kind, then "other"
    const Clock::time_point t0{};
    EXPECT_TRUE(limiter.admit("a", t0, 3));
    EXPECT_TRUE(limiter.admit("a", t0, 3));
    EXPECT_TRUE(limiter.admit("b", t0, 3));   // "other", first
    EXPECT_FALSE(limiter.admit("c", t0, 3));  // "other" writes one line a window
    EXPECT_TRUE(limiter.admit("a", t0, 3));
    EXPECT_FALSE(limiter.admit("a", t0, 3));
}

}  // namespace
}  // namespace gport::mavlink::bridge
