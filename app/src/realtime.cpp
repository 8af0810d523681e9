#include "gport/app/realtime.hpp"

#include <fmt/format.h>
#include <sched.h>
#include <sys/mman.h>

#include <cerrno>
#include <cstring>

namespace gport::app {
namespace {

int set_fifo(int priority) {
    sched_param param{};
    param.sched_priority = priority;
    return ::sched_setscheduler(0, SCHED_FIFO, &param) == 0 ? 0 : errno;
}

int current_fifo() {
    sched_param param{};
    if (::sched_getscheduler(0) != SCHED_FIFO || ::sched_getparam(0, &param) != 0) {
        return 0;
    }
    return param.sched_priority;
}

int lock_all() {
    return ::mlockall(MCL_CURRENT | MCL_FUTURE) == 0 ? 0 : errno;
}

void apply_priority(int priority, const RealtimeCalls& calls, RealtimeOutcome& out) {
    if (const int already = calls.current_fifo(); already != 0) {
        out.applied.push_back(fmt::format(
            "realtime.priority {}: already SCHED_FIFO priority {} (set by the service manager, "
            "e.g. CPUSchedulingPolicy=fifo); left as it is",
            priority, already));
        return;
    }
    if (const int error = calls.set_fifo(priority); error != 0) {
        out.warnings.push_back(fmt::format(
            "realtime.priority {}: SCHED_FIFO refused ({}); running with normal scheduling. "
            "It needs CAP_SYS_NICE or an RLIMIT_RTPRIO of at least {} (LimitRTPRIO=), and no "
            "RestrictRealtime=; under the shipped unit's sandbox set CPUSchedulingPolicy=fifo "
            "and CPUSchedulingPriority= in a drop-in instead (docs/configuration.md)",
            priority, std::strerror(error), priority));
        return;
    }
    out.applied.push_back(fmt::format("realtime.priority {}: running SCHED_FIFO", priority));
}

void apply_lock(const RealtimeCalls& calls, RealtimeOutcome& out) {
    if (const int error = calls.lock_all(); error != 0) {
        out.warnings.push_back(fmt::format(
            "realtime.lock_memory: mlockall refused ({}); memory may be paged out. It needs "
            "CAP_IPC_LOCK or an RLIMIT_MEMLOCK above the daemon's size (LimitMEMLOCK=infinity), "
            "and under the shipped unit's sandbox SystemCallFilter=@memlock in a drop-in "
            "(docs/configuration.md)",
            std::strerror(error)));
        return;
    }
    out.applied.push_back("realtime.lock_memory: all memory locked (mlockall)");
}

}  // namespace

RealtimeCalls system_realtime_calls() {
    return {set_fifo, current_fifo, lock_all};
}

RealtimeOutcome apply_realtime(const config::RealtimeConfig& realtime, const RealtimeCalls& calls) {
    RealtimeOutcome out;
    if (realtime.priority > 0) {
        apply_priority(realtime.priority, calls, out);
    }
    if (realtime.lock_memory) {
        apply_lock(calls, out);
    }
    return out;
}

}  // namespace gport::app
