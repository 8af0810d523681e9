// realtime.priority and realtime.lock_memory: real-time scheduling and locked
// memory, applied once at start, as chronyd's -P and -m do. A refusal (no
// privilege, a sandbox's RestrictRealtime= or system-call filter) is reported
// and the daemon runs on normally: never fatal.
#pragma once

#include <string>
#include <vector>

#include "gport/config/config.hpp"

namespace gport::app {

// The system calls, replaceable by tests. Each returns 0 or an errno value.
struct RealtimeCalls {
    int (*set_fifo)(int priority);  // sched_setscheduler(0, SCHED_FIFO, priority)
    int (*current_fifo)();          // the current SCHED_FIFO priority, 0 when not FIFO
    int (*lock_all)();              // mlockall(MCL_CURRENT | MCL_FUTURE)
};
RealtimeCalls system_realtime_calls();

struct RealtimeOutcome {
    std::vector<std::string> applied;   // info lines: what took effect
    std::vector<std::string> warnings;  // warn lines: what was refused, why, what to do
};

RealtimeOutcome apply_realtime(const config::RealtimeConfig& realtime,
                               const RealtimeCalls& calls = system_realtime_calls());

}  // namespace gport::app
