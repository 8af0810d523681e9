// Test support (and the benchmarks'): a child process, by default with its
// stdout read line by line on a background thread, so tests can wait for
// what it prints.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace gport::testing {

using namespace std::chrono_literals;

// How a Process starts; the defaults are what the tests need.
struct Launch {
    enum class Output {
        kLines,    // stdout read line by line (next_line ...); stderr is ours
        kInherit,  // stdout and stderr are ours
        kFile,     // stdout and stderr go to `file`, truncated
    };
    std::vector<std::string> env;  // "NAME=value" entries added to our environment
    Output output = Output::kLines;
    std::string file;
    // SCHED_FIFO at priority 5 (what a unit's CPUSchedulingPolicy=fifo does;
    // below the benchmarks' measuring threads); it exits 126 when refused.
    bool realtime = false;
    // A pipe as its descriptor 3, whose read end report() is: the child's
    // way to say it is ready (the benchmarks' children).
    bool report = false;
};

class Process {
  public:
    // Starts argv[0] with the arguments and, added to our environment, the
    // "NAME=value" entries of env; stderr is passed through to ours.
    explicit Process(std::vector<std::string> argv, std::vector<std::string> env = {});
    // Starts argv[0] as `launch` says. Throws std::system_error naming the
    // call that failed (pipe2, fork, open).
    Process(std::vector<std::string> argv, const Launch& launch);
    ~Process();
    Process(const Process&) = delete;
    Process& operator=(const Process&) = delete;

    pid_t pid() const { return pid_; }
    bool running();
    void signal(int sig);
    // Waits for the exit; returns the exit status (128+N for signal N), or
    // empty when it did not exit in time.
    std::optional<int> wait(std::chrono::milliseconds timeout = 10s);
    // SIGTERM, then SIGKILL if it has not exited within `timeout`; the exit
    // status as wait() gives it (already exited: its status).
    int terminate(std::chrono::milliseconds timeout = 5s);
    // The read end of the report pipe (Launch::report), else -1.
    int report() const { return report_; }

    // The next line of stdout not yet taken, waiting up to timeout.
    std::optional<std::string> next_line(std::chrono::milliseconds timeout = 10s);
    // Takes lines until one satisfies pred; returns it, or empty on timeout.
    std::optional<std::string> wait_line(const std::function<bool(const std::string&)>& pred,
                                         std::chrono::milliseconds timeout = 10s);
    // Every line read so far and not yet taken, without waiting.
    std::vector<std::string> drain();

  private:
    void read_loop(int fd);

    pid_t pid_ = -1;
    int report_ = -1;
    std::optional<int> status_;
    std::thread reader_;
    std::mutex mutex_;
    std::condition_variable cv_;
    std::deque<std::string> lines_;
    bool eof_ = false;
};

// A fresh temporary directory, PARENT/PREFIX-XXXXXX (the system's temporary
// directory by default), removed with its contents at destruction unless
// kept. Throws std::system_error naming the directory it could not make.
class TempDir {
  public:
    explicit TempDir(const std::string& prefix = "gport-test", std::string parent = {});
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const std::string& path() const { return path_; }
    std::string file(const std::string& name) const { return path_ + "/" + name; }
    // Leaves the directory in place for someone to read (a benchmark's logs
    // after a failed or --keep-logs run).
    void keep() { keep_ = true; }

  private:
    std::string path_;
    bool keep_ = false;
};

// Polls pred every 10 ms until it holds or the timeout passes.
bool eventually(const std::function<bool()>& pred, std::chrono::milliseconds timeout = 10s);

}  // namespace gport::testing
