// base/futex.hpp: a wait sleeps for as long as it was asked, on every target.
// On 32-bit ARM this file is also built with -D_TIME_BITS=64 (base_tests_time64,
// Debian 13's armhf default), where a wait that handed the C library's 64-bit
// timespec to the old futex call returned at once: a reader busy-spun.
#include "gport/base/futex.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <ctime>
#include <thread>

// The time64 build really has a 64-bit time_t (and long stays 32-bit).
#if defined(_TIME_BITS) && _TIME_BITS == 64
static_assert(sizeof(std::time_t) == 8);
#endif

namespace gport::base {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

TEST(Futex, AWaitOnAnUnchangedWordSleepsItsWholeTimeout) {
    std::atomic<std::uint32_t> word{5};
    const auto start = Clock::now();
    EXPECT_EQ(futex_wait(word, 5, 300ms), FutexWait::kTimedOut);
    // Only a lower bound: the machine may be slow, never early. (The bug
    // returned after 0 ms.)
    EXPECT_GE(Clock::now() - start, 250ms);
}

TEST(Futex, SecondsAndNanosecondsBothCount) {
    std::atomic<std::uint32_t> word{1};
    const auto start = Clock::now();
    EXPECT_EQ(futex_wait(word, 1, 1s + 100ms), FutexWait::kTimedOut);
    EXPECT_GE(Clock::now() - start, 1s);
}

TEST(Futex, AWaitReturnsAtOnceWhenTheWordAlreadyChanged) {
    std::atomic<std::uint32_t> word{5};
    EXPECT_EQ(futex_wait(word, 4, 10s), FutexWait::kChanged);
}

TEST(Futex, ANegativeOrZeroTimeoutDoesNotSleep) {
    std::atomic<std::uint32_t> word{5};
    EXPECT_EQ(futex_wait(word, 5, -1s), FutexWait::kTimedOut);
    EXPECT_EQ(futex_wait(word, 5, 0ns), FutexWait::kTimedOut);
}

TEST(Futex, AWakeEndsAWaitBeforeItsTimeout) {
    std::atomic<std::uint32_t> word{0};
    std::atomic<bool> done{false};
    std::thread waker([&] {
        while (!done.load()) {
            word.store(1);
            futex_wake_all(word);
            std::this_thread::sleep_for(10ms);
        }
    });
    const auto result = futex_wait(word, 0, 60s);
    done.store(true);
    waker.join();
    EXPECT_TRUE(result == FutexWait::kWoken || result == FutexWait::kChanged);
}

}  // namespace
}  // namespace gport::base
