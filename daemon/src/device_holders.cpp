#include "gport/daemon/device_holders.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <csignal>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <optional>
#include <system_error>

namespace gport::daemon {
namespace {

namespace fs = std::filesystem;

// What identifies one device: its number, and the lock files that name it.
struct Target {
    std::optional<dev_t> rdev;
    std::vector<std::string> lock_names;
};

std::optional<dev_t> char_device(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0 || !S_ISCHR(st.st_mode)) {
        return std::nullopt;
    }
    return st.st_rdev;
}

Target target_of(const std::string& device) {
    Target t;
    t.rdev = char_device(device);
    if (!t.rdev) {
        return t;
    }
    t.lock_names.push_back("LCK.." + fs::path(device).filename().string());
    std::error_code ec;
    const auto resolved = fs::canonical(device, ec);
    const auto other = "LCK.." + resolved.filename().string();
    if (!ec && other != t.lock_names.front()) {
        t.lock_names.push_back(other);
    }
    return t;
}

// A decimal PID that fits pid_t (32 bits on every Linux ABI), else none.
std::optional<pid_t> parse_pid(std::string_view text) {
    long long value = 0;
    const auto* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, value);
    if (ec != std::errc() || ptr != end || value <= 0 ||
        value > std::numeric_limits<std::int32_t>::max()) {
        return std::nullopt;
    }
    return static_cast<pid_t>(value);
}

std::string comm_of(const std::string& proc, pid_t pid) {
    std::ifstream in(fmt::format("{}/{}/comm", proc, pid));
    std::string name;
    if (!std::getline(in, name) || name.empty()) {
        return "?";
    }
    return name;
}

bool alive(pid_t pid) {
    return pid > 0 && (::kill(pid, 0) == 0 || errno == EPERM);
}

// The first bytes of a lock file. /run/lock is writable by every user
// (mode 1777), and the probe runs as root: a link is not followed (it could
// name /dev/watchdog, which opening arms), a FIFO does not block, and
// anything but a regular file is no lock.
std::string lock_bytes(const std::string& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
    if (fd < 0) {
        return "";
    }
    struct stat st {};
    std::string bytes(64, '\0');
    ssize_t n = -1;
    if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode)) {
        n = ::read(fd, bytes.data(), bytes.size());
    }
    ::close(fd);
    bytes.resize(n > 0 ? static_cast<std::size_t>(n) : 0);
    return bytes;
}

// The PID in a lock file: ASCII digits with blanks around them, or a
// native binary 32-bit int (exactly 4 bytes that are not all ASCII).
std::optional<pid_t> lock_pid(const std::string& path) {
    const auto bytes = lock_bytes(path);
    const auto first = bytes.find_first_not_of(" \t\r\n");
    const auto last = bytes.find_last_not_of(" \t\r\n");
    if (first != std::string::npos) {
        if (auto pid = parse_pid(std::string_view(bytes).substr(first, last - first + 1))) {
            return pid;
        }
    }
    if (bytes.size() == sizeof(std::int32_t)) {
        std::int32_t value = 0;
        std::memcpy(&value, bytes.data(), sizeof value);
        return value > 0 ? std::optional<pid_t>(static_cast<pid_t>(value)) : std::nullopt;
    }
    return std::nullopt;
}

void add_holder(DeviceHolders& into, DeviceHolder holder) {
    const auto same = [&](const DeviceHolder& h) { return h.pid == holder.pid; };
    if (std::none_of(into.holders.begin(), into.holders.end(), same)) {
        into.holders.push_back(std::move(holder));
    }
}

// The character device an fd link names, if it is one under /dev/.
std::optional<dev_t> fd_device(const fs::path& link) {
    std::error_code ec;
    const auto path = fs::read_symlink(link, ec).string();
    if (ec || path.rfind("/dev/", 0) != 0) {
        return std::nullopt;
    }
    return char_device(link.string());
}

// Marks the targets process `pid` has open; false when its descriptors
// could not be read (it may have exited since: that is no holder).
bool scan_process(const std::string& proc, pid_t pid, const std::vector<Target>& targets,
                  std::vector<DeviceHolders>& out) {
    std::error_code ec;
    fs::directory_iterator it(fmt::format("{}/{}/fd", proc, pid), ec);
    if (ec) {
        return ec == std::errc::no_such_file_or_directory || ec == std::errc::no_such_process;
    }
    for (fs::directory_iterator end; !ec && it != end; it.increment(ec)) {
        const auto rdev = fd_device(it->path());
        for (std::size_t i = 0; rdev && i < targets.size(); ++i) {
            if (targets[i].rdev == rdev) {
                add_holder(out[i], {pid, comm_of(proc, pid), {}});
            }
        }
    }
    return true;
}

void scan_processes(const HolderPlaces& places, pid_t except, const std::vector<Target>& targets,
                    std::vector<DeviceHolders>& out) {
    std::size_t unchecked = 0;
    std::error_code ec;
    for (fs::directory_iterator it(places.proc, ec), end; !ec && it != end; it.increment(ec)) {
        const auto pid = parse_pid(it->path().filename().string());
        if (pid && *pid != except && !scan_process(places.proc, *pid, targets, out)) {
            ++unchecked;
        }
    }
    for (auto& d : out) {
        d.unchecked = unchecked;
    }
}

void scan_locks(const HolderPlaces& places, pid_t except, const Target& target,
                DeviceHolders& out) {
    for (const auto& name : target.lock_names) {
        const auto path = places.locks + "/" + name;
        const auto pid = lock_pid(path);
        if (pid && *pid != except && alive(*pid)) {
            add_holder(out, {*pid, comm_of(places.proc, *pid), path});
        }
    }
}

}  // namespace

std::vector<DeviceHolders> device_holders(const std::vector<std::string>& devices, pid_t except,
                                          const HolderPlaces& places) {
    std::vector<Target> targets;
    std::transform(devices.begin(), devices.end(), std::back_inserter(targets), target_of);
    std::vector<DeviceHolders> out(devices.size());
    const auto is_device = [](const Target& t) { return t.rdev.has_value(); };
    if (std::any_of(targets.begin(), targets.end(), is_device)) {
        scan_processes(places, except, targets, out);
    }
    for (std::size_t i = 0; i < targets.size(); ++i) {
        scan_locks(places, except, targets[i], out[i]);
    }
    return out;
}

std::string describe_holders(const std::vector<DeviceHolder>& holders) {
    constexpr std::size_t kNamed = 3;
    std::string text;
    for (std::size_t i = 0; i < holders.size() && i < kNamed; ++i) {
        const auto& h = holders[i];
        text += fmt::format("{}PID {} {}", i == 0 ? "" : ", ", h.pid, h.name);
        if (!h.lock.empty()) {
            text += fmt::format(" (lock file {})", h.lock);
        }
    }
    if (holders.size() > kNamed) {
        text += fmt::format(" and {} more", holders.size() - kNamed);
    }
    return text;
}

}  // namespace gport::daemon
