#include "process.hpp"

#include <fcntl.h>
#include <sched.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace gport::testing {

namespace {

// A pipe whose both ends close on exec; throws naming the call.
std::array<int, 2> make_pipe() {
    std::array<int, 2> fds{};
    if (::pipe2(fds.data(), O_CLOEXEC) != 0) {
        throw std::system_error(errno, std::generic_category(), "pipe2");
    }
    return fds;
}

// In the child, before exec: `fd` as descriptor `target`, kept across exec.
void place(int fd, int target) {
    if (fd == target) {
        ::fcntl(fd, F_SETFD, 0);
    } else {
        ::dup2(fd, target);  // the copy does not close on exec
    }
}

}  // namespace

namespace {

Launch with_env(std::vector<std::string> env) {
    Launch launch;
    launch.env = std::move(env);
    return launch;
}

}  // namespace

Process::Process(std::vector<std::string> argv, std::vector<std::string> env)
    : Process(std::move(argv), with_env(std::move(env))) {}

Process::Process(std::vector<std::string> argv, const Launch& launch) {
    using Output = Launch::Output;
    std::array<int, 2> out{-1, -1};
    std::array<int, 2> report{-1, -1};
    int file = -1;
    if (launch.output == Output::kLines) {
        out = make_pipe();
    } else if (launch.output == Output::kFile) {
        file = ::open(launch.file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
        if (file < 0) {
            throw std::system_error(errno, std::generic_category(), "open " + launch.file);
        }
    }
    if (launch.report) {
        report = make_pipe();
    }
    std::vector<char*> args;
    for (auto& a : argv) {
        args.push_back(a.data());
    }
    args.push_back(nullptr);
    auto env = launch.env;
    pid_ = ::fork();
    if (pid_ < 0) {
        throw std::system_error(errno, std::generic_category(), "fork");
    }
    if (pid_ == 0) {
        if (out[1] >= 0) {
            place(out[1], STDOUT_FILENO);
        }
        if (file >= 0) {
            place(file, STDOUT_FILENO);
            place(file, STDERR_FILENO);
        }
        if (report[1] >= 0) {
            place(report[1], 3);
        }
        for (auto& e : env) {
            ::putenv(e.data());
        }
        if (launch.realtime) {
            sched_param param{};
            param.sched_priority = 5;
            if (::sched_setscheduler(0, SCHED_FIFO, &param) != 0) {
                ::_exit(126);
            }
        }
        ::execv(args[0], args.data());
        ::_exit(127);
    }
    for (const int fd : {out[1], report[1], file}) {
        if (fd >= 0) {
            ::close(fd);
        }
    }
    report_ = report[0];
    if (out[0] >= 0) {
        reader_ = std::thread([this, fd = out[0]] { read_loop(fd); });
    }
}

Process::~Process() {
    if (running()) {
        signal(SIGKILL);
        wait(5s);
    }
    if (reader_.joinable()) {
        reader_.join();
    }
    if (report_ >= 0) {
        ::close(report_);
    }
}

int Process::terminate(std::chrono::milliseconds timeout) {
    signal(SIGTERM);
    if (auto status = wait(timeout)) {
        return *status;
    }
    signal(SIGKILL);
    while (running()) {
        std::this_thread::sleep_for(10ms);
    }
    return *status_;
}

void Process::read_loop(int fd) {
    std::string partial;
    char buf[4096];
    for (;;) {
        const ssize_t n = ::read(fd, buf, sizeof buf);
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n <= 0) {
            break;
        }
        partial.append(buf, static_cast<std::size_t>(n));
        std::size_t pos;
        while ((pos = partial.find('\n')) != std::string::npos) {
            std::lock_guard lock(mutex_);
            lines_.push_back(partial.substr(0, pos));
            partial.erase(0, pos + 1);
            cv_.notify_all();
        }
    }
    ::close(fd);
    std::lock_guard lock(mutex_);
    eof_ = true;
    cv_.notify_all();
}

bool Process::running() {
    if (status_) {
        return false;
    }
    int status = 0;
    const pid_t r = ::waitpid(pid_, &status, WNOHANG);
    if (r == pid_) {
        status_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        return false;
    }
    return true;
}

void Process::signal(int sig) {
    if (running()) {
        ::kill(pid_, sig);
    }
}

std::optional<int> Process::wait(std::chrono::milliseconds timeout) {
    eventually([this] { return !running(); }, timeout);
    return status_;
}

std::optional<std::string> Process::next_line(std::chrono::milliseconds timeout) {
    std::unique_lock lock(mutex_);
    if (!cv_.wait_for(lock, timeout, [this] { return !lines_.empty() || eof_; }) ||
        lines_.empty()) {
        return std::nullopt;
    }
    std::string line = std::move(lines_.front());
    lines_.pop_front();
    return line;
}

std::optional<std::string> Process::wait_line(const std::function<bool(const std::string&)>& pred,
                                              std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
            deadline - std::chrono::steady_clock::now());
        if (left.count() <= 0) {
            return std::nullopt;
        }
        auto line = next_line(left);
        if (!line) {
            return std::nullopt;
        }
        if (pred(*line)) {
            return line;
        }
    }
}

std::vector<std::string> Process::drain() {
    std::lock_guard lock(mutex_);
    std::vector<std::string> out(lines_.begin(), lines_.end());
    lines_.clear();
    return out;
}

TempDir::TempDir(const std::string& prefix, std::string parent) {
    if (parent.empty()) {
        parent = std::filesystem::temp_directory_path().string();
    }
    std::string templ = parent + "/" + prefix + "-XXXXXX";
    if (::mkdtemp(templ.data()) == nullptr) {
        throw std::system_error(errno, std::generic_category(), "mkdtemp " + templ);
    }
    path_ = templ;
}

TempDir::~TempDir() {
    if (!keep_) {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
}

bool eventually(const std::function<bool()>& pred, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (!pred()) {
        if (std::chrono::steady_clock::now() >= deadline) {
            return false;
        }
        std::this_thread::sleep_for(10ms);
    }
    return true;
}

}  // namespace gport::testing
