#include "posix.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <thread>

#include "unix_connect.hpp"

namespace gport::bench {

std::int64_t now_ns() {
    timespec ts{};
    ::clock_gettime(CLOCK_MONOTONIC, &ts);
    return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

Fd& Fd::operator=(Fd&& other) noexcept {
    if (this != &other) {
        reset(other.release());
    }
    return *this;
}

int Fd::release() {
    const int fd = fd_;
    fd_ = -1;
    return fd;
}

void Fd::reset(int fd) {
    if (fd_ >= 0) {
        ::close(fd_);
    }
    fd_ = fd;
}

Fd connect_unix(const std::string& path) {
    Fd fd(testing::connect_unix(path));
    if (!fd.valid()) {
        throw std::runtime_error("connect " + path + ": " + std::strerror(errno));
    }
    ::fcntl(fd.get(), F_SETFL, ::fcntl(fd.get(), F_GETFL) | O_NONBLOCK);
    return fd;
}

std::optional<Fd> connect_unix_retry(const std::string& path, int timeout_ms) {
    const auto deadline = now_ns() + std::int64_t{timeout_ms} * 1'000'000;
    while (true) {
        try {
            return connect_unix(path);
        } catch (const std::runtime_error&) {
            if (now_ns() > deadline) {
                return std::nullopt;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
    }
}

namespace {

// Waits until fd is ready for `events`; false after the deadline.
bool wait_ready(int fd, short events, std::int64_t deadline) {
    const auto left_ms = (deadline - now_ns()) / 1'000'000;
    if (left_ms < 0) {
        return false;
    }
    pollfd p{fd, events, 0};
    const int rc = ::poll(&p, 1, static_cast<int>(left_ms) + 1);
    return rc > 0 || (rc < 0 && errno == EINTR);
}

}  // namespace

bool write_all(int fd, std::string_view data, int timeout_ms) {
    const auto deadline = now_ns() + std::int64_t{timeout_ms} * 1'000'000;
    while (!data.empty()) {
        const auto n = ::send(fd, data.data(), data.size(), MSG_NOSIGNAL);
        if (n > 0) {
            data.remove_prefix(static_cast<std::size_t>(n));
            continue;
        }
        if (n < 0 && errno != EAGAIN && errno != EINTR) {
            return false;
        }
        if (!wait_ready(fd, POLLOUT, deadline)) {
            return false;
        }
    }
    return true;
}

bool read_line(int fd, std::string& pending, std::string& line, int timeout_ms) {
    const auto deadline = now_ns() + std::int64_t{timeout_ms} * 1'000'000;
    while (true) {
        if (const auto newline = pending.find('\n'); newline != std::string::npos) {
            line.assign(pending, 0, newline);
            pending.erase(0, newline + 1);
            return true;
        }
        char buffer[65536];
        const auto n = ::read(fd, buffer, sizeof(buffer));
        if (n > 0) {
            pending.append(buffer, static_cast<std::size_t>(n));
            continue;
        }
        if (n == 0 || (errno != EAGAIN && errno != EINTR)) {
            return false;
        }
        if (!wait_ready(fd, POLLIN, deadline)) {
            return false;
        }
    }
}

namespace {

// The value after "<key>:" in /proc/<pid>/status, in kB.
long status_field(const std::string& text, std::string_view key) {
    const auto at = text.find(key);
    if (at == std::string::npos) {
        return 0;
    }
    return std::strtol(text.c_str() + at + key.size() + 1, nullptr, 10);
}

}  // namespace

ProcSample sample_process(pid_t pid) {
    ProcSample sample;
    std::ifstream stat_file("/proc/" + std::to_string(pid) + "/stat");
    std::string stat;
    if (!std::getline(stat_file, stat)) {
        return sample;
    }
    // Fields after the command name (which may hold spaces) start at ") ";
    // utime and stime are fields 14 and 15, i.e. the 12th and 13th after it.
    std::istringstream fields(stat.substr(stat.rfind(')') + 2));
    std::string skip;
    for (int i = 0; i < 11; ++i) {
        fields >> skip;
    }
    unsigned long long utime = 0;
    unsigned long long stime = 0;
    fields >> utime >> stime;
    const auto ticks = static_cast<double>(::sysconf(_SC_CLK_TCK));
    sample.cpu_seconds = static_cast<double>(utime + stime) / ticks;
    sample.system_seconds = static_cast<double>(stime) / ticks;
    std::ifstream status_file("/proc/" + std::to_string(pid) + "/status");
    std::stringstream status;
    status << status_file.rdbuf();
    sample.rss_kib = status_field(status.str(), "VmRSS");
    sample.hwm_kib = status_field(status.str(), "VmHWM");
    // A zombie has no memory left; it is not alive for our purposes.
    sample.alive = status.str().find("State:\tZ") == std::string::npos;
    return sample;
}

std::string load_average() {
    std::ifstream file("/proc/loadavg");
    std::string one;
    std::string five;
    std::string fifteen;
    file >> one >> five >> fifteen;
    return one + " " + five + " " + fifteen;
}

void raise_fd_limit() {
    rlimit limit{};
    if (::getrlimit(RLIMIT_NOFILE, &limit) == 0 && limit.rlim_cur < limit.rlim_max) {
        limit.rlim_cur = limit.rlim_max;
        ::setrlimit(RLIMIT_NOFILE, &limit);
    }
}

std::unique_ptr<testing::Process> spawn_self(std::vector<std::string> args,
                                             const std::string& what) {
    std::error_code error;
    const auto self = std::filesystem::read_symlink("/proc/self/exe", error);
    if (error) {
        throw std::runtime_error(what + ": cannot start: /proc/self/exe: " + error.message());
    }
    args.at(0) = self.string();
    testing::Launch launch;
    launch.output = testing::Launch::Output::kInherit;
    launch.report = true;
    try {
        return std::make_unique<testing::Process>(std::move(args), launch);
    } catch (const std::system_error& e) {
        throw std::runtime_error(what + ": cannot start: " + e.what());
    }
}

}  // namespace gport::bench
