// Waiting on and waking a 32-bit word in shared memory (Linux futex(2)),
// for the shared-memory attitude channel (wake_block.hpp). The word must
// be in a MAP_SHARED mapping for waiters in other processes: these use the
// shared (not _PRIVATE) futex operations. A read-only mapping is enough to
// wait and to wake.
#pragma once

#include <linux/futex.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cstdint>

namespace gport::base {

enum class FutexWait { kWoken, kChanged, kTimedOut, kInterrupted };

namespace futex_detail {

// The timeouts are given to the kernel in its own layouts, never in the C
// library's timespec, whose size follows the C library's time_t and not the
// system call being made:
// - 64-bit targets: SYS_futex takes two 64-bit longs.
// - 32-bit targets (armhf): SYS_futex takes two 32-bit longs, whatever
//   _TIME_BITS says (with _TIME_BITS=64, Debian 13's armhf default, the libc
//   timespec is 64-bit and the kernel would read its seconds' low and high
//   halves as seconds and nanoseconds); SYS_futex_time64 (Linux 5.1) takes
//   two 64-bit integers. It is tried first; a kernel without it (ENOSYS)
//   gets the old call, with the seconds capped to what 32 bits hold.
struct OldTimespec {
    long tv_sec;
    long tv_nsec;
};
struct Timespec64 {
    std::int64_t tv_sec;
    std::int64_t tv_nsec;
};

inline long wait(const std::uint32_t* word, std::uint32_t seen, std::int64_t ns) {
    const std::int64_t sec = ns / 1'000'000'000;
    const std::int64_t nsec = ns % 1'000'000'000;
#if defined(SYS_futex_time64)
    const Timespec64 t64{sec, nsec};
    const long rc = ::syscall(SYS_futex_time64, word, FUTEX_WAIT, seen, &t64, nullptr, 0);
    if (rc == 0 || errno != ENOSYS) {
        return rc;
    }
#endif
    const OldTimespec old{static_cast<long>(std::min<std::int64_t>(sec, LONG_MAX)),
                          static_cast<long>(nsec)};
    return ::syscall(SYS_futex, word, FUTEX_WAIT, seen, &old, nullptr, 0);
}

}  // namespace futex_detail

// Sleeps while `word` still holds `seen`, at most `timeout`. kChanged: the
// word no longer held `seen` when the kernel looked (no sleep at all).
inline FutexWait futex_wait(const std::atomic<std::uint32_t>& word, std::uint32_t seen,
                            std::chrono::nanoseconds timeout) {
    const std::int64_t ns = timeout.count() < 0 ? 0 : timeout.count();
    const long rc = futex_detail::wait(reinterpret_cast<const std::uint32_t*>(&word), seen, ns);
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
