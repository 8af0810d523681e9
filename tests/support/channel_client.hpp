// Test support: a raw client of gportd's socket that reads with recvmsg and
// keeps the descriptors that come with the lines (the attitude_channel
// reply: the ring and the connection's wake block), and read-only mappings
// of the shared-memory attitude channel's two blocks.
// Header-only; the ipc, integration and benchmark code may all use it.
#pragma once

#include <poll.h>
#include <sys/mman.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <deque>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "gport/base/attitude_ring.hpp"
#include "gport/base/descriptors.hpp"
#include "gport/base/wake_block.hpp"
#include "unix_connect.hpp"

namespace gport::testing {

class DescriptorClient {
  public:
    explicit DescriptorClient(const std::string& path) { fd_ = connect_unix(path); }
    ~DescriptorClient() {
        base::close_descriptors(descriptors_);
        if (fd_ >= 0) {
            ::close(fd_);
        }
    }
    DescriptorClient(const DescriptorClient&) = delete;
    DescriptorClient& operator=(const DescriptorClient&) = delete;

    bool connected() const { return fd_ >= 0; }
    int socket() const { return fd_; }

    bool send(const std::string& text) {
        return ::send(fd_, text.data(), text.size(), MSG_NOSIGNAL) ==
               static_cast<ssize_t>(text.size());
    }

    // Sends a request and returns its reply, keeping any lines before it.
    nlohmann::json call(const std::string& method, const nlohmann::json& params = nullptr) {
        const int id = ++id_;
        nlohmann::json request = {{"jsonrpc", "2.0"}, {"id", id}, {"method", method}};
        if (!params.is_null()) {
            request["params"] = params;
        }
        send(request.dump() + "\n");
        while (auto line = next()) {
            if (line->contains("id") && (*line)["id"] == id) {
                return *line;
            }
            kept_.push_back(*line);
        }
        return nullptr;
    }

    // The next line, parsed (kept lines first); empty on timeout or EOF.
    std::optional<nlohmann::json> next(
        std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
        if (!kept_.empty()) {
            auto line = kept_.front();
            kept_.pop_front();
            return line;
        }
        const auto deadline = std::chrono::steady_clock::now() + timeout;
        for (;;) {
            if (auto nl = buffer_.find('\n'); nl != std::string::npos) {
                auto line = nlohmann::json::parse(buffer_.substr(0, nl));
                buffer_.erase(0, nl + 1);
                return line;
            }
            if (!fill(deadline)) {
                return std::nullopt;
            }
        }
    }

    // The first descriptor received and not taken yet, or -1. The caller owns it.
    int take_descriptor() { return base::take_descriptor(descriptors_); }
    std::size_t descriptors() const { return descriptors_.size(); }
    // Reads at most this many bytes per recvmsg (a slow reader).
    void read_chunk(std::size_t bytes) { chunk_ = bytes < sizeof(data_) ? bytes : sizeof(data_); }

  private:
    bool fill(std::chrono::steady_clock::time_point deadline) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
            deadline - std::chrono::steady_clock::now());
        pollfd p{fd_, POLLIN, 0};
        if (fd_ < 0 || left.count() <= 0 || ::poll(&p, 1, static_cast<int>(left.count())) <= 0) {
            return false;
        }
        const auto n = base::receive_with_descriptors(fd_, data_, chunk_, descriptors_);
        if (n <= 0) {
            return false;
        }
        buffer_.append(data_, static_cast<std::size_t>(n));
        return true;
    }

    int fd_ = -1;
    int id_ = 0;
    char data_[65536];
    std::size_t chunk_ = sizeof(data_);
    std::string buffer_;
    std::deque<nlohmann::json> kept_;
    std::deque<int> descriptors_;
};

// A read-only, shared mapping of the channel's descriptor.
class RingMapping {
  public:
    RingMapping(int fd, std::size_t size) : size_(size) {
        void* memory = ::mmap(nullptr, size, PROT_READ, MAP_SHARED, fd, 0);
        memory_ = memory == MAP_FAILED ? nullptr : memory;
    }
    ~RingMapping() {
        if (memory_ != nullptr) {
            ::munmap(memory_, size_);
        }
    }
    RingMapping(const RingMapping&) = delete;
    RingMapping& operator=(const RingMapping&) = delete;

    bool mapped() const { return memory_ != nullptr; }
    void* memory() const { return memory_; }
    std::size_t size() const { return size_; }
    std::optional<std::string> check() const { return base::RingReader::check(memory_, size_); }
    base::RingReader reader() const { return base::RingReader(memory_, size_); }

  private:
    void* memory_ = nullptr;
    std::size_t size_;
};

// A read-only, shared mapping of a connection's wake block.
class WakeMapping {
  public:
    explicit WakeMapping(int fd) {
        void* memory = ::mmap(nullptr, base::kWakeBlockBytes, PROT_READ, MAP_SHARED, fd, 0);
        memory_ = memory == MAP_FAILED ? nullptr : memory;
    }
    ~WakeMapping() {
        if (memory_ != nullptr) {
            ::munmap(memory_, base::kWakeBlockBytes);
        }
    }
    WakeMapping(const WakeMapping&) = delete;
    WakeMapping& operator=(const WakeMapping&) = delete;

    bool mapped() const { return memory_ != nullptr; }
    std::optional<std::string> check() const {
        return base::check_wake_block(memory_, base::kWakeBlockBytes);
    }
    const std::atomic<std::uint32_t>& word() const { return base::wake_word(memory_); }

  private:
    void* memory_ = nullptr;
};

}  // namespace gport::testing
