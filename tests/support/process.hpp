// Test support: a child process with its stdout read line by line on a
// background thread, so tests can wait for what it prints.
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

class Process {
  public:
    // Starts argv[0] with the arguments and, added to our environment, the
    // "NAME=value" entries of env; stderr is passed through to ours.
    explicit Process(std::vector<std::string> argv, std::vector<std::string> env = {});
    ~Process();
    Process(const Process&) = delete;
    Process& operator=(const Process&) = delete;

    pid_t pid() const { return pid_; }
    bool running();
    void signal(int sig);
    // Waits for the exit; returns the exit status (128+N for signal N), or
    // empty when it did not exit in time.
    std::optional<int> wait(std::chrono::milliseconds timeout = 10s);

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
