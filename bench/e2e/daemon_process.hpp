// The real gportd as a child process: a temporary config file, fork/exec,
// SIGTERM and the exit status.
#pragma once

#include <sys/types.h>

#include <string>
#include <vector>

#include "process.hpp"

namespace gport::bench {

struct DaemonOptions {
    std::string binary;       // path to gportd
    std::string device;       // serial device (our pty slave or a simulator's link)
    std::string socket;       // Unix socket path
    std::string config_path;  // where the config file is written
    std::string log_path;     // the daemon's stdout and stderr go here
    int max_clients = 1100;
    int max_duration_ms = 600000;
    std::string log_level = "warn";
    // Run gportd SCHED_FIFO (what a unit's CPUSchedulingPolicy=fifo does), to
    // tell the daemon's own delays from the time it waits for a CPU.
    bool realtime = false;
    // realtime.priority in the config (with lock_memory): gportd applies it itself.
    int realtime_priority = 0;
    // socket.max_requests_per_s; 0 = leave gportd's default (200).
    int max_requests_per_s = 100000;
    std::string socket_mode = "0600";
    std::string extra_config;             // more top-level members, e.g. "access": {...}
    std::vector<std::string> extra_args;  // more arguments, e.g. --state-dir DIR
};

// Writes a gportd config (JSON with comments) for a benchmark run.
void write_daemon_config(const DaemonOptions& options);

// gportd (or any program) as a child: tests/support's Process, its output
// in a log file.
class DaemonProcess {
  public:
    // Writes the config and starts gportd. Throws std::runtime_error when the
    // binary cannot be started.
    explicit DaemonProcess(const DaemonOptions& options);
    // Starts any program (argv[0] is its path) with stdout and stderr going
    // to `log_path`: the comparison with gpsd runs gpsd through this.
    DaemonProcess(const std::vector<std::string>& argv, const std::string& log_path);
    ~DaemonProcess();
    DaemonProcess(const DaemonProcess&) = delete;
    DaemonProcess& operator=(const DaemonProcess&) = delete;

    pid_t pid() const { return process_.pid(); }
    // True while the child has not exited.
    bool running() { return process_.running(); }
    // Sends SIGTERM and waits (at most timeout_ms, then SIGKILL). Returns the
    // exit status, or 128 + signal when it was killed by one.
    int terminate(int timeout_ms = 5000);

  private:
    testing::Process process_;
};

}  // namespace gport::bench
