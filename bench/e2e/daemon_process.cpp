#include "daemon_process.hpp"

#include <fcntl.h>
#include <sched.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <thread>

#include "posix.hpp"

namespace gport::bench {

void write_daemon_config(const DaemonOptions& options) {
    std::ofstream out(options.config_path);
    out << "// Written by the gportd benchmark for one run; see docs/performance.md.\n"
        << "{\n"
        << "    // Room for the 1000-subscriber case plus the flooding and control clients,\n"
        << "    // all of them under the benchmark's one uid.\n"
        << "    \"socket\": {\"max_clients\": " << options.max_clients
        << ", \"max_clients_per_uid\": " << options.max_clients << ", \"mode\": \""
        << options.socket_mode << "\"";
    if (options.max_requests_per_s > 0) {
        // The flood cells measure the loop, not the per-client rate limit.
        out << ",\n               \"max_requests_per_s\": " << options.max_requests_per_s;
    }
    out << "},\n"
        << "    // One speed command lasts the whole run, so keepalive ticks are never reset.\n"
        << "    \"keepalive\": {\"max_duration_ms\": " << options.max_duration_ms << "},\n"
        << "    \"log\": {\"level\": \"" << options.log_level << "\"}";
    if (options.realtime_priority > 0) {  // only when asked: older gportd builds lack the key
        out << ",\n    \"realtime\": {\"priority\": " << options.realtime_priority
            << ", \"lock_memory\": true}";
    }
    if (!options.extra_config.empty()) {
        out << ",\n    " << options.extra_config;
    }
    out << "\n"
        << "}\n";
    if (!out) {
        throw std::runtime_error("cannot write the daemon config " + options.config_path);
    }
}

DaemonProcess::DaemonProcess(const DaemonOptions& options) {
    write_daemon_config(options);
    if (::access(options.binary.c_str(), X_OK) != 0) {
        throw std::runtime_error("gportd not executable at " + options.binary +
                                 " (pass --gportd PATH)");
    }
    std::vector<std::string> argv = {options.binary, "--config", options.config_path, "--device",
                                     options.device, "--socket", options.socket};
    argv.insert(argv.end(), options.extra_args.begin(), options.extra_args.end());
    spawn(argv, options.log_path, options.realtime);
}

DaemonProcess::DaemonProcess(const std::vector<std::string>& argv, const std::string& log_path) {
    if (argv.empty() || ::access(argv[0].c_str(), X_OK) != 0) {
        throw std::runtime_error("not executable: " + (argv.empty() ? std::string() : argv[0]));
    }
    spawn(argv, log_path, false);
}

void DaemonProcess::spawn(const std::vector<std::string>& argv, const std::string& log_path,
                          bool realtime) {
    std::vector<char*> args;
    for (const auto& a : argv) {
        args.push_back(const_cast<char*>(a.c_str()));
    }
    args.push_back(nullptr);
    pid_ = ::fork();
    if (pid_ < 0) {
        throw std::runtime_error(std::string("fork: ") + std::strerror(errno));
    }
    if (pid_ == 0) {
        const int log = ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (log >= 0) {
            ::dup2(log, STDOUT_FILENO);
            ::dup2(log, STDERR_FILENO);
        }
        if (realtime) {
            sched_param param{};
            param.sched_priority = 5;  // below the benchmark's measuring threads (10)
            if (::sched_setscheduler(0, SCHED_FIFO, &param) != 0) {
                ::_exit(126);
            }
        }
        ::execv(args[0], args.data());
        ::_exit(127);
    }
}

DaemonProcess::~DaemonProcess() {
    if (!reaped_ && pid_ > 0) {
        terminate(2000);
    }
}

bool DaemonProcess::running() {
    if (reaped_) {
        return false;
    }
    if (::waitpid(pid_, &status_, WNOHANG) == pid_) {
        reaped_ = true;
        return false;
    }
    return true;
}

int DaemonProcess::terminate(int timeout_ms) {
    if (!running()) {
        return status_ == -1        ? -1
               : WIFEXITED(status_) ? WEXITSTATUS(status_)
                                    : 128 + WTERMSIG(status_);
    }
    ::kill(pid_, SIGTERM);
    const auto deadline = now_ns() + std::int64_t{timeout_ms} * 1'000'000;
    while (running() && now_ns() < deadline) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (!reaped_) {
        ::kill(pid_, SIGKILL);
        ::waitpid(pid_, &status_, 0);
        reaped_ = true;
    }
    return WIFEXITED(status_) ? WEXITSTATUS(status_) : 128 + WTERMSIG(status_);
}

}  // namespace gport::bench
