// TokenBucket: full when made, refills at its rate up to its burst, and a
// charge can put it into debt (down to one burst), which take() then waits out.
#include "gport/base/token_bucket.hpp"

#include <gtest/gtest.h>

namespace gport::base {
namespace {

using namespace std::chrono_literals;
using Clock = TokenBucket::Clock;

TEST(TokenBucket, StartsFullAndRefusesWhenEmpty) {
    TokenBucket bucket(5, 5);
    const auto t0 = Clock::time_point{} + 100s;
    for (int i = 0; i < 5; ++i) {
        EXPECT_TRUE(bucket.take(t0)) << i;
    }
    EXPECT_FALSE(bucket.take(t0));
    EXPECT_GT(bucket.wait_for(t0), 190ms);
    EXPECT_LE(bucket.wait_for(t0), 201ms);
    EXPECT_TRUE(bucket.take(t0 + 200ms)) << "one token a fifth of a second";
    EXPECT_FALSE(bucket.take(t0 + 200ms));
}

TEST(TokenBucket, NeverHoldsMoreThanItsBurst) {
    TokenBucket bucket(5, 5);
    const auto t0 = Clock::time_point{} + 100s;
    EXPECT_TRUE(bucket.take(t0));
    EXPECT_DOUBLE_EQ(bucket.level(t0 + 1h), 5.0);
}

TEST(TokenBucket, AChargeIsDebtThatTakeWaitsOut) {
    TokenBucket bucket(10, 10);
    const auto t0 = Clock::time_point{} + 100s;
    bucket.charge(t0, 1000);
    EXPECT_DOUBLE_EQ(bucket.level(t0), -10.0) << "debt is bounded by one burst";
    EXPECT_FALSE(bucket.take(t0 + 1s));
    EXPECT_TRUE(bucket.take(t0 + 2100ms));
}

TEST(TokenBucket, ATimeBeforeTheLastCountsAsNoTime) {
    TokenBucket bucket(10, 10);
    const auto t0 = Clock::time_point{} + 100s;
    for (int i = 0; i < 10; ++i) {
        ASSERT_TRUE(bucket.take(t0));
    }
    EXPECT_FALSE(bucket.take(t0 - 50s)) << "a clock going back refills nothing";
}

}  // namespace
}  // namespace gport::base
