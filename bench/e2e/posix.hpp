// Small POSIX helpers shared by the end-to-end benchmark and the soak driver:
// a monotonic clock in nanoseconds, an owning file descriptor, Unix socket
// clients, and what /proc tells about another process.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "process.hpp"

namespace gport::bench {

// CLOCK_MONOTONIC in nanoseconds: the one clock every thread stamps with.
std::int64_t now_ns();

// Owns one file descriptor; closes it when destroyed.
class Fd {
  public:
    Fd() = default;
    explicit Fd(int fd) : fd_(fd) {}
    Fd(Fd&& other) noexcept : fd_(other.release()) {}
    Fd& operator=(Fd&& other) noexcept;
    Fd(const Fd&) = delete;
    Fd& operator=(const Fd&) = delete;
    ~Fd() { reset(); }

    int get() const { return fd_; }
    bool valid() const { return fd_ >= 0; }
    int release();
    void reset(int fd = -1);

  private:
    int fd_ = -1;
};

// Connects to a Unix stream socket (blocking connect, so a full accept
// backlog waits instead of failing), then makes it non-blocking. Throws
// std::runtime_error naming the path and the error.
Fd connect_unix(const std::string& path);

// Tries to connect until `timeout_ms` passed (the daemon may still be
// starting); nullopt when it never answered.
std::optional<Fd> connect_unix_retry(const std::string& path, int timeout_ms);

// Writes all of `data` to a non-blocking descriptor, waiting with poll()
// when the socket buffer is full. False on error or after `timeout_ms`.
bool write_all(int fd, std::string_view data, int timeout_ms = 5000);

// Reads one '\n'-terminated line from a non-blocking descriptor into `line`
// (without the newline), keeping extra bytes in `pending` for the next call.
// False on EOF, error or timeout.
bool read_line(int fd, std::string& pending, std::string& line, int timeout_ms = 5000);

// What /proc says about a process: CPU time used (user + system) and memory.
struct ProcSample {
    double cpu_seconds = 0;     // utime + stime from /proc/<pid>/stat
    double system_seconds = 0;  // stime alone: time in the kernel (syscalls)
    long rss_kib = 0;           // VmRSS from /proc/<pid>/status
    long hwm_kib = 0;           // VmHWM: the peak resident size
    bool alive = false;         // false when the process is gone
};
ProcSample sample_process(pid_t pid);

// The first three fields of /proc/loadavg, e.g. "1.52 0.98 0.61".
std::string load_average();

// Raises RLIMIT_NOFILE's soft limit to the hard limit (children inherit it):
// a thousand subscribers need a thousand descriptors on both ends.
void raise_fd_limit();

// This program started again (its own path, from /proc/self/exe, as
// args[0]) with `args` and a pipe as its descriptor 3, whose read end
// (Process::report()) the parent reads the child's first line from; its
// output is ours. Throws "WHAT: cannot start: ..." when it cannot start.
// Destroying the Process kills and reaps the child.
std::unique_ptr<testing::Process> spawn_self(std::vector<std::string> args,
                                             const std::string& what);

}  // namespace gport::bench
