// A stand-in for gportd in the shared-memory channel tests: a listening Unix
// socket in a temporary directory and a thread that answers one connection
// at a time. `attitude_channel` is answered with a memfd the test formats
// with base::RingWriter (or corrupts), attached with SCM_RIGHTS to the reply
// line, as gportd does (docs/api.md); `subscribe` / `unsubscribe` echo the
// topics; the test may also push lines, with or without a descriptor.
#pragma once

#include <sys/mman.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "gport/base/attitude_ring.hpp"
#include "gport/base/futex.hpp"

namespace gport::testing {

// A memfd holding a ring, mapped read-write for the test to publish into.
class RingBlock {
  public:
    explicit RingBlock(std::uint32_t slots = 64) : size_(base::ring_bytes(slots)) {
        fd_ = ::memfd_create("fake-gportd-attitude", MFD_CLOEXEC);
        if (fd_ < 0 || ::ftruncate(fd_, static_cast<off_t>(size_)) != 0) {
            throw std::runtime_error("memfd_create/ftruncate failed");
        }
        memory_ = ::mmap(nullptr, size_, PROT_READ | PROT_WRITE, MAP_SHARED, fd_, 0);
        if (memory_ == MAP_FAILED) {
            throw std::runtime_error("mmap failed");
        }
        writer_.emplace(memory_, slots);
    }
    RingBlock(const RingBlock&) = delete;
    RingBlock& operator=(const RingBlock&) = delete;
    ~RingBlock() {
        ::munmap(memory_, size_);
        ::close(fd_);
    }

    // Publishes sample number `seq` (imu roll = seq / 10) and wakes readers.
    void publish(std::uint64_t seq, bool rates = false) {
        base::RingSample s;
        s.seq = seq;
        s.t = 1700000000.0 + static_cast<double>(seq) / 100;
        s.imu = {static_cast<double>(seq) / 10, -2.5, 45};
        s.hall = {0.5, -2.25, 44.75};
        s.has_rates = rates;
        s.hall_rates = {1, 2, 3};
        s.imu_rates = {4, 5, 6};
        writer_->publish(s);
        base::futex_wake_all(writer_->wake_word());
    }
    void close() {
        writer_->close();
        base::futex_wake_all(writer_->wake_word());
    }
    // Overwrites the header's first word (magic) for the bad-block tests.
    void corrupt_magic() { *static_cast<std::uint32_t*>(memory_) = 0xdeadbeef; }
    void set_version(std::uint32_t v) { static_cast<std::uint32_t*>(memory_)[1] = v; }
    int fd() const { return fd_; }
    std::size_t size() const { return size_; }

  private:
    std::size_t size_;
    int fd_ = -1;
    void* memory_ = nullptr;
    std::optional<base::RingWriter> writer_;
};

inline std::size_t open_descriptors() {
    std::size_t n = 0;
    for ([[maybe_unused]] const auto& entry :
         std::filesystem::directory_iterator("/proc/self/fd")) {
        ++n;
    }
    return n;
}

class FakeServer {
  public:
    FakeServer() {
        char dir[] = "/tmp/gport-shm-XXXXXX";
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
    FakeServer(const FakeServer&) = delete;
    FakeServer& operator=(const FakeServer&) = delete;
    ~FakeServer() {
        stopping_ = true;
        ::shutdown(listener_, SHUT_RDWR);
        drop();
        thread_.join();
        ::close(listener_);
        std::filesystem::remove_all(dir_);
    }

    const std::string& path() const { return path_; }

    // What `attitude_channel` answers with: the block's descriptor (or none).
    void offer(const RingBlock* block) {
        std::lock_guard lock(mutex_);
        offers_.push_back(block);
    }
    // Sends a line to the connected client, with `fd` attached when >= 0.
    void push(const nlohmann::json& message, int fd = -1) {
        for (int i = 0; i < 500; ++i) {  // the accept may lag the client's connect
            std::unique_lock lock(mutex_);
            if (client_ >= 0) {
                send_line(message.dump() + "\n", fd);
                return;
            }
            lock.unlock();
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        throw std::runtime_error("no client connected to the fake server");
    }
    // The topics of the last subscribe request.
    nlohmann::json last_subscribe() {
        std::lock_guard lock(mutex_);
        return last_subscribe_;
    }
    // Closes the current connection (the client sees gportd go away).
    void drop() {
        std::lock_guard lock(mutex_);
        if (client_ >= 0) {
            ::shutdown(client_, SHUT_RDWR);
        }
    }

  private:
    void serve() {
        while (!stopping_) {
            const int fd = ::accept4(listener_, nullptr, nullptr, SOCK_CLOEXEC);
            if (fd < 0) {
                return;
            }
            {
                std::lock_guard lock(mutex_);
                client_ = fd;
            }
            read_requests(fd);
            std::lock_guard lock(mutex_);
            ::close(fd);
            client_ = -1;
        }
    }

    void read_requests(int fd) {
        std::string buffer;
        char chunk[4096];
        while (true) {
            const auto n = ::read(fd, chunk, sizeof(chunk));
            if (n <= 0) {
                return;
            }
            buffer.append(chunk, static_cast<std::size_t>(n));
            for (auto nl = buffer.find('\n'); nl != std::string::npos; nl = buffer.find('\n')) {
                answer(nlohmann::json::parse(buffer.substr(0, nl)));
                buffer.erase(0, nl + 1);
            }
        }
    }

    void answer(const nlohmann::json& request) {
        std::lock_guard lock(mutex_);
        const std::string method = request.at("method");
        nlohmann::json reply = {{"jsonrpc", "2.0"}, {"id", request.at("id")}};
        int fd = -1;
        if (method == "attitude_channel") {
            const RingBlock* block = nullptr;
            if (!offers_.empty()) {
                block = offers_.front();
                offers_.erase(offers_.begin());
            }
            reply["result"] = {{"version", 1},
                               {"slots", 64},
                               {"size", block ? block->size() : 0},
                               {"published", 0}};
            fd = block ? block->fd() : -1;
        } else if (method == "subscribe" || method == "unsubscribe") {
            const auto params = request.value("params", nlohmann::json::object());
            if (method == "subscribe") {
                last_subscribe_ = params.value("topics", nlohmann::json::array());
            }
            reply["result"] = {{"topics", params.value("topics", nlohmann::json::array())}};
        } else {
            reply["error"] = {{"code", -32601}, {"message", "unknown method " + method}};
        }
        send_line(reply.dump() + "\n", fd);
    }

    // Caller holds mutex_. The descriptor goes with the line's first byte.
    void send_line(const std::string& line, int fd) {
        iovec io{const_cast<char*>(line.data()), line.size()};
        msghdr message{};
        message.msg_iov = &io;
        message.msg_iovlen = 1;
        alignas(cmsghdr) char control[CMSG_SPACE(sizeof(int))]{};
        if (fd >= 0) {
            message.msg_control = control;
            message.msg_controllen = sizeof(control);
            cmsghdr* c = CMSG_FIRSTHDR(&message);
            c->cmsg_level = SOL_SOCKET;
            c->cmsg_type = SCM_RIGHTS;
            c->cmsg_len = CMSG_LEN(sizeof(int));
            std::memcpy(CMSG_DATA(c), &fd, sizeof(int));
        }
        if (client_ >= 0) {
            [[maybe_unused]] const auto n = ::sendmsg(client_, &message, MSG_NOSIGNAL);
        }
    }

    std::string dir_;
    std::string path_;
    int listener_ = -1;
    int client_ = -1;
    std::atomic<bool> stopping_{false};
    std::mutex mutex_;
    std::vector<const RingBlock*> offers_;
    nlohmann::json last_subscribe_;
    std::thread thread_;
};

}  // namespace gport::testing
