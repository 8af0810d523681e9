// Waiting on and waking a 32-bit word in shared memory (Linux futex(2)),
// for the shared-memory attitude channel (wake_block.hpp). The word must
// be in a MAP_SHARED mapping for waiters in other processes: these use the
// shared (not _PRIVATE) futex operations. A read-only mapping is enough to
// wait and to wake.
#pragma once

#include <linux/futex.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cstdint>
#include <ctime>

namespace gport::base {

enum class FutexWait { kWoken, kChanged, kTimedOut, kInterrupted };

// Sleeps while `word` still holds `seen`, at most `timeout`. kChanged: the
// word no longer held `seen` when the kernel looked (no sleep at all).
inline FutexWait futex_wait(const std::atomic<std::uint32_t>& word, std::uint32_t seen,
                            std::chrono::nanoseconds timeout) {
    const auto ns = timeout.count() < 0 ? 0 : timeout.count();
    timespec relative{static_cast<time_t>(ns / 1'000'000'000),
                      static_cast<long>(ns % 1'000'000'000)};
    const long rc = ::syscall(SYS_futex, reinterpret_cast<const std::uint32_t*>(&word), FUTEX_WAIT,
                              seen, &relative, nullptr, 0);
    if (rc == 0) {
        return FutexWait::kWoken;
    }
    switch (errno) {
        case EAGAIN:
            return FutexWait::kChanged;
        case ETIMEDOUT:
            return FutexWait::kTimedOut;
        default:
            return FutexWait::kInterrupted;
    }
}

// Wakes at most `count` waiters on `word`; returns how many were woken, or
// -1 (errno). The kernel only reads the word's address: a read-only
// mapping is enough.
inline long futex_wake(const std::atomic<std::uint32_t>& word, int count) {
    return ::syscall(SYS_futex, reinterpret_cast<const std::uint32_t*>(&word), FUTEX_WAKE, count,
                     nullptr, nullptr, 0);
}

// Wakes every waiter on `word`.
inline long futex_wake_all(const std::atomic<std::uint32_t>& word) {
    return futex_wake(word, INT_MAX);
}

static_assert(sizeof(std::atomic<std::uint32_t>) == sizeof(std::uint32_t));

}  // namespace gport::base
