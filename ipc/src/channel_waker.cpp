#include "channel_waker.hpp"

#include <sched.h>
#include <signal.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

namespace gport::ipc::detail {
namespace {

// A read, a walk over a short vector and syscalls need far less; and with
// realtime.lock_memory (mlockall) this is what the thread adds to the RSS.
constexpr std::size_t kStack = 128 * 1024;

std::string waker_failed(const char* step, int error) {
    return std::string(step) + ": " + std::strerror(error);
}

// The thread inherits the loop's scheduling. Under realtime.priority it
// would compete with the loop at the loop's priority while the walks a
// reader can make long run (with the futex bucket's lock held, which no
// priority preempts): it goes back to normal scheduling. The shipped
// unit's filter refuses sched_setscheduler (EPERM); there gportd only runs
// SCHED_FIFO when the unit says so (CPUSchedulingPolicy=), and the thread
// keeps it.
void leave_realtime() {
    int policy = SCHED_OTHER;
    sched_param param{};
    if (::pthread_getschedparam(::pthread_self(), &policy, &param) == 0 &&
        (policy == SCHED_FIFO || policy == SCHED_RR)) {
        const sched_param normal{};
        ::pthread_setschedparam(::pthread_self(), SCHED_OTHER, &normal);
    }
}

}  // namespace

ChannelWaker::~ChannelWaker() {
    close();
    delete mailbox_.exchange(nullptr, std::memory_order_acq_rel);
    if (event_ >= 0) {
        ::close(event_);
    }
}

std::optional<std::string> ChannelWaker::start() {
    if (started_ || closed_) {
        return closed_ ? std::optional<std::string>("the channel is closed") : std::nullopt;
    }
    if (event_ < 0) {
        event_ = ::eventfd(0, EFD_CLOEXEC);
        if (event_ < 0) {
            return waker_failed("eventfd (waker thread)", errno);
        }
    }
    pthread_attr_t attr;
    ::pthread_attr_init(&attr);
    ::pthread_attr_setstacksize(&attr, kStack);
    // Every signal stays with the loop (its signal_set): the thread blocks them all.
    sigset_t all;
    sigset_t previous;
    ::sigfillset(&all);
    ::pthread_sigmask(SIG_SETMASK, &all, &previous);
    const int error = ::pthread_create(&thread_, &attr, &ChannelWaker::main, this);
    ::pthread_sigmask(SIG_SETMASK, &previous, nullptr);
    ::pthread_attr_destroy(&attr);
    if (error != 0) {
        return waker_failed("starting the waker thread", error);
    }
    // Named here, not by the thread itself: it has its name once start() returns.
    ::pthread_setname_np(thread_, "gportd-waker");
    started_ = true;
    return std::nullopt;
}

void ChannelWaker::set_blocks(Blocks blocks) {
    all_ = std::move(blocks);
    split();
}

void ChannelWaker::split() {
    inline_.clear();
    Blocks threaded;
    for (const auto& block : all_) {
        if (inline_.size() < kInline && block->strikes() < kStrikes) {
            inline_.push_back(block);
        } else {
            threaded.push_back(block);
        }
    }
    threaded_ = !threaded.empty();
    auto* fresh = new Blocks(std::move(threaded));
    delete mailbox_.exchange(fresh, std::memory_order_acq_rel);  // one the thread never took
}

void ChannelWaker::signal() {
    if (!running()) {
        return;
    }
    // Read before the loop's wakes: a connection handed to the thread by
    // them was woken for this sample already, and the thread's round would
    // wake it twice.
    const bool threaded = threaded_;
    wake_inline();
    if (!threaded) {
        return;
    }
    requested_.fetch_add(1, std::memory_order_acq_rel);
    if (!signalled_.exchange(true, std::memory_order_acq_rel)) {
        notify();  // the thread took the previous signal: it may be asleep
    }
}

// At most kInline wakes; a connection whose wakes were slow kStrikes times
// is the thread's from the next sample on.
void ChannelWaker::wake_inline() {
    bool hand_over = false;
    for (const auto& block : inline_) {
        const auto start = Clock::now();
        block->bump_and_wake();
        if (Clock::now() - start > slow_wake_ && block->strike() >= kStrikes) {
            ++handed_over_;
            hand_over = true;
        }
    }
    if (hand_over) {
        split();
    }
}

void ChannelWaker::close() {
    if (!started_ || closed_) {
        closed_ = true;
        return;
    }
    wake_inline();  // their last wake; the thread's round below makes the others'
    closed_ = true;
    stopping_.store(true, std::memory_order_release);
    requested_.fetch_add(1, std::memory_order_acq_rel);
    signalled_.store(true, std::memory_order_release);
    notify();
    ::pthread_join(thread_, nullptr);
}

// The counter never nears its maximum (at most a few writes per read), so
// the write never blocks.
void ChannelWaker::notify() {
    const std::uint64_t one = 1;
    while (::write(event_, &one, sizeof(one)) < 0 && errno == EINTR) {
    }
}

void* ChannelWaker::main(void* self) {
    static_cast<ChannelWaker*>(self)->run();
    return nullptr;
}

void ChannelWaker::run() {
    leave_realtime();
    for (;;) {
        std::uint64_t count = 0;
        if (::read(event_, &count, sizeof(count)) < 0 && errno == EINTR) {
            continue;
        }
        // Taken before the round: a signal given during it makes another.
        signalled_.exchange(false, std::memory_order_acq_rel);
        const auto requested = requested_.load(std::memory_order_acquire);
        take_blocks();
        const bool last = stopping_.load(std::memory_order_acquire);
        round();
        handled_.store(requested, std::memory_order_release);
        if (last) {
            return;
        }
    }
}

void ChannelWaker::take_blocks() {
    if (Blocks* fresh = mailbox_.exchange(nullptr, std::memory_order_acq_rel)) {
        blocks_ = std::move(*fresh);  // the blocks nobody else holds are unmapped here
        delete fresh;
    }
}

// One bump and FUTEX_WAKE(1) per reader connection the loop does not wake.
void ChannelWaker::round() {
    for (const auto& block : blocks_) {
        block->bump_and_wake();
    }
    rounds_.fetch_add(1, std::memory_order_relaxed);
}

}  // namespace gport::ipc::detail
