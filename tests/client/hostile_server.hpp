// A stand-in for gportd that misbehaves on purpose, for the tests of the
// client's limits (issue 22 item 7): a listening Unix socket in a temporary
// directory and a thread that accepts one connection and runs a script for
// each request line (or reads nothing at all). The script answers, floods,
// streams a line without end or stays silent; what it sent is counted.
// Also the process's memory figures (VmHWM) the tests bound.
#pragma once

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <string_view>
#include <thread>

namespace gport::testing {

inline constexpr std::uint64_t kMiB = 1024 * 1024;

// The connection as a script sees it.
class HostilePeer {
  public:
    explicit HostilePeer(int fd, std::atomic<std::uint64_t>& sent) : fd_(fd), sent_(sent) {}

    // False once the client is gone (it closed, or the test ends).
    bool send(std::string_view bytes) {
        while (!bytes.empty()) {
            const auto n = ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL);
            if (n < 0 && errno == EINTR) {
                continue;
            }
            if (n <= 0) {
                return false;
            }
            sent_ += static_cast<std::uint64_t>(n);
            bytes.remove_prefix(static_cast<std::size_t>(n));
        }
        return true;
    }
    bool send_line(const nlohmann::json& message) { return send(message.dump() + "\n"); }
    bool reply(const nlohmann::json& request, const nlohmann::json& result) {
        return send_line({{"jsonrpc", "2.0"}, {"id", request.at("id")}, {"result", result}});
    }
    // `total` bytes of `fill` in 1 MiB writes, without a newline; stops
    // early (false) when the client goes away.
    bool stream(std::uint64_t total, char fill = 'a') {
        const std::string chunk(1 << 20, fill);
        for (std::uint64_t left = total; left > 0;) {
            const auto n = std::min<std::uint64_t>(left, chunk.size());
            if (!send(std::string_view(chunk.data(), n))) {
                return false;
            }
            left -= n;
        }
        return true;
    }

    // Ends the connection from the server's side.
    void hang_up() { ::shutdown(fd_, SHUT_RDWR); }

  private:
    int fd_;
    std::atomic<std::uint64_t>& sent_;
};

class HostileServer {
  public:
    using Script = std::function<void(HostilePeer& peer, const nlohmann::json& request)>;

    // `script` runs on the server's thread for each request line; without
    // one the server never reads what the client sends.
    explicit HostileServer(Script script) : script_(std::move(script)) {
        char dir[] = "/tmp/gport-hostile-XXXXXX";
        if (::mkdtemp(dir) == nullptr) {
            throw std::runtime_error("mkdtemp failed");
        }
        dir_ = dir;
        path_ = dir_ + "/gportd.sock";
        listener_ = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
        sockaddr_un address{};
        address.sun_family = AF_UNIX;
        std::strncpy(address.sun_path, path_.c_str(), sizeof(address.sun_path) - 1);
        if (::bind(listener_, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0 ||
            ::listen(listener_, 4) != 0) {
            throw std::runtime_error("cannot listen on " + path_);
        }
        thread_ = std::thread([this] { serve(); });
    }
    HostileServer(const HostileServer&) = delete;
    HostileServer& operator=(const HostileServer&) = delete;
    ~HostileServer() {
        stopping_ = true;
        ::shutdown(listener_, SHUT_RDWR);
        {
            std::lock_guard lock(mutex_);
            if (client_ >= 0) {
                ::shutdown(client_, SHUT_RDWR);  // ends a send the client no longer reads
            }
        }
        thread_.join();
        ::close(listener_);
        std::filesystem::remove_all(dir_);
    }

    const std::string& path() const { return path_; }
    std::uint64_t bytes_sent() const { return sent_; }
    // True once the client closed its end (the server read EOF).
    bool client_closed() const { return client_closed_; }

  private:
    void serve() {
        const int fd = ::accept4(listener_, nullptr, nullptr, SOCK_CLOEXEC);
        if (fd < 0) {
            return;
        }
        {
            std::lock_guard lock(mutex_);
            client_ = fd;
        }
        HostilePeer peer(fd, sent_);
        if (script_) {
            read_requests(fd, peer);
        } else {
            while (!stopping_) {
                std::this_thread::sleep_for(std::chrono::milliseconds(10));
            }
        }
        std::lock_guard lock(mutex_);
        ::close(fd);
        client_ = -1;
    }

    void read_requests(int fd, HostilePeer& peer) {
        std::string buffer;
        char chunk[65536];
        while (!stopping_) {
            const auto n = ::read(fd, chunk, sizeof(chunk));
            if (n <= 0) {
                client_closed_ = n == 0;
                return;
            }
            buffer.append(chunk, static_cast<std::size_t>(n));
            for (auto nl = buffer.find('\n'); nl != std::string::npos; nl = buffer.find('\n')) {
                const auto request = nlohmann::json::parse(buffer.substr(0, nl));
                buffer.erase(0, nl + 1);
                script_(peer, request);
            }
        }
    }

    Script script_;
    std::string dir_;
    std::string path_;
    int listener_ = -1;
    int client_ = -1;
    std::atomic<bool> stopping_{false};
    std::atomic<bool> client_closed_{false};
    std::atomic<std::uint64_t> sent_{0};
    std::mutex mutex_;
    std::thread thread_;
};

// Peak RSS says nothing under AddressSanitizer (shadow memory, the
// quarantine of freed blocks), nor under qemu-user (GPORT_EMULATED: a
// cross build's tests; the process's peak is the emulator's too, whose
// translated code grows with what runs): there the tests check their other
// bounds (counts, bytes read, errors), with smaller floods, and the RSS
// bounds are the native Release build's check.
#if defined(__SANITIZE_ADDRESS__) || defined(GPORT_SANITIZED) || defined(GPORT_EMULATED)
inline constexpr bool kRssMeasured = false;
#else
inline constexpr bool kRssMeasured = true;
#endif

// The process's peak resident set (VmHWM), in KiB.
inline std::uint64_t peak_rss_kib() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line)) {
        if (line.rfind("VmHWM:", 0) == 0) {
            return std::strtoull(line.c_str() + 6, nullptr, 10);
        }
    }
    throw std::runtime_error("no VmHWM in /proc/self/status");
}

// Resets the peak to the current resident set where the kernel allows it
// (clear_refs "5", Linux 4.0); returns the peak to measure growth from.
inline std::uint64_t reset_peak_rss() {
    std::ofstream("/proc/self/clear_refs") << "5";
    return peak_rss_kib();
}

// How much the peak grew since `before` (reset_peak_rss()); zero when the
// kernel's per-thread RSS counters, synced in batches, read a little lower.
inline std::uint64_t peak_rss_growth_kib(std::uint64_t before) {
    const auto peak = peak_rss_kib();
    return peak > before ? peak - before : 0;
}

// An attitude notification as gportd sends it.
inline nlohmann::json attitude_notification(std::uint64_t seq) {
    const nlohmann::json axes = {{"roll", 0.5}, {"pitch", -2.25}, {"yaw", 44.75}};
    return {{"jsonrpc", "2.0"},
            {"method", "attitude"},
            {"params", {{"seq", seq}, {"t", 1.7e9}, {"imu", axes}, {"hall", axes}}}};
}

}  // namespace gport::testing
