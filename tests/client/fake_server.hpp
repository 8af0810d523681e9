// A stand-in for gportd in the shared-memory channel tests: a listening Unix
// socket in a temporary directory and a thread that answers one connection
// at a time. `attitude_channel` is answered as gportd does (docs/api.md): the
// next offer's ring and wake block, formatted by the test, attached with
// SCM_RIGHTS to the reply line ("descriptors":2), or with no offer left
// "descriptors":0; `subscribe` / `unsubscribe` echo the topics; the test may
// also push lines, with or without descriptors.
#pragma once

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "gport/base/attitude_ring.hpp"
#include "gport/base/descriptors.hpp"
#include "gport/base/futex.hpp"
#include "gport/base/wake_block.hpp"

namespace gport::testing {

// The seals gportd puts on both blocks.
inline constexpr unsigned kSeals = F_SEAL_SHRINK | F_SEAL_GROW | F_SEAL_FUTURE_WRITE | F_SEAL_SEAL;

// A memfd of `size` bytes mapped read-write for the test, sealed with
// `seals` afterwards (0: none), as gportd makes its blocks.
class SealedMemory {
  public:
    SealedMemory(const char* name, std::size_t size, unsigned seals) : size_(size) {
        fd_ = ::memfd_create(name, MFD_CLOEXEC | MFD_ALLOW_SEALING);
        if (fd_ < 0 || ::ftruncate(fd_, static_cast<off_t>(size_)) != 0) {
            throw std::runtime_error("memfd_create/ftruncate failed");
        }
        memory_ = ::mmap(nullptr, size_, PROT_READ | PROT_WRITE, MAP_SHARED, fd_, 0);
        if (memory_ == MAP_FAILED) {
            throw std::runtime_error("mmap failed");
        }
        seals_ = seals;
    }
    SealedMemory(const SealedMemory&) = delete;
    SealedMemory& operator=(const SealedMemory&) = delete;
    ~SealedMemory() {
        ::munmap(memory_, size_);
        ::close(fd_);
    }
    // Seals it (after the test formatted it).
    void seal() {
        if (seals_ != 0 && ::fcntl(fd_, F_ADD_SEALS, seals_) != 0) {
            throw std::runtime_error("F_ADD_SEALS failed");
        }
    }
    void* memory() const { return memory_; }
    int fd() const { return fd_; }
    std::size_t size() const { return size_; }

  private:
    std::size_t size_;
    int fd_ = -1;
    void* memory_ = nullptr;
    unsigned seals_ = 0;
};

// A ring and its connection's wake block, mapped read-write for the test to
// publish into; the test keeps its writable mappings, so it can also play a
// hostile server that rewrites the blocks after the client checked them.
class RingBlock {
  public:
    explicit RingBlock(std::uint32_t slots = 64, unsigned seals = kSeals)
        : ring_("fake-gportd-attitude", base::ring_bytes(slots), seals),
          wake_("fake-gportd-wake", base::kWakeBlockBytes, seals),
          slots_(slots) {
        writer_.emplace(ring_.memory(), slots);
        word_ = &base::format_wake_block(wake_.memory())->wake;
        ring_.seal();
        wake_.seal();
    }

    // Publishes sample number `seq` (imu roll = seq / 10), bumps the word
    // and wakes `wakes` waiters (gportd: 1).
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
        bump();
    }
    void close() {
        writer_->close();
        bump();
    }
    void bump() {
        word_->fetch_add(1, std::memory_order_release);
        base::futex_wake(*word_, wakes);
    }
    // Overwrites a header word (u32 index) of the ring.
    void set_header(std::size_t index, std::uint32_t value) {
        static_cast<std::uint32_t*>(ring_.memory())[index] = value;
    }
    void corrupt_magic() { set_header(0, 0xdeadbeef); }
    void set_version(std::uint32_t v) { set_header(1, v); }
    int fd() const { return ring_.fd(); }
    int wake_fd() const { return wake_.fd(); }
    std::size_t size() const { return ring_.size(); }
    std::uint32_t slots() const { return slots_; }
    int wakes = INT_MAX;  // waiters each bump wakes

  private:
    SealedMemory ring_;
    SealedMemory wake_;
    std::uint32_t slots_;
    std::optional<base::RingWriter> writer_;
    std::atomic<std::uint32_t>* word_ = nullptr;
};

// What one attitude_channel request is answered with: `block` as gportd
// sends it (nullptr: no descriptor), or a hostile variant: `fds` attached
// instead (when set), `result` members changed; `late`: held back until
// release_held() or the next attitude_channel request, answered first.
struct Offer {
    const RingBlock* block = nullptr;
    std::optional<std::vector<int>> fds;
    nlohmann::json result = nlohmann::json::object();
    bool late = false;
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

    // What the next `attitude_channel` answers with: the block's descriptors
    // (nullptr: none, though "descriptors":2 is announced).
    void offer(const RingBlock* block) { offer(Offer{block, std::nullopt, {}}); }
    void offer(Offer offer) {
        std::lock_guard lock(mutex_);
        offers_.push_back(std::move(offer));
    }
    // Sends a line to the connected client, with `fds` attached.
    void push(const nlohmann::json& message, std::vector<int> fds = {}) {
        for (int i = 0; i < 500; ++i) {  // the accept may lag the client's connect
            std::unique_lock lock(mutex_);
            if (client_ >= 0) {
                send_line(message.dump() + "\n", fds);
                return;
            }
            lock.unlock();
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        throw std::runtime_error("no client connected to the fake server");
    }
    // Sends the replies held back (Offer::late), in order.
    void release_held() {
        std::lock_guard lock(mutex_);
        send_held();
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
        std::vector<int> fds;
        if (method == "attitude_channel") {
            if (!offers_.empty() && offers_.front().late) {
                held_.emplace_back(request.at("id"), std::move(offers_.front()));
                offers_.erase(offers_.begin());
                return;
            }
            send_held();
            reply["result"] = channel_result(fds);
        } else if (method == "subscribe" || method == "unsubscribe") {
            const auto params = request.value("params", nlohmann::json::object());
            if (method == "subscribe") {
                last_subscribe_ = params.value("topics", nlohmann::json::array());
            }
            reply["result"] = {{"topics", params.value("topics", nlohmann::json::array())}};
        } else {
            reply["error"] = {{"code", -32601}, {"message", "unknown method " + method}};
        }
        send_line(reply.dump() + "\n", fds);
    }

    // Caller holds mutex_.
    void send_held() {
        for (auto& [id, offer] : held_) {
            std::vector<int> fds;
            nlohmann::json reply = {{"jsonrpc", "2.0"}, {"id", id}};
            reply["result"] = offer_result(offer, fds);
            send_line(reply.dump() + "\n", fds);
        }
        held_.clear();
    }

    // Caller holds mutex_. The next offer, or "descriptors":0 without one.
    nlohmann::json channel_result(std::vector<int>& fds) {
        if (offers_.empty()) {
            return plain_result();
        }
        Offer offer = std::move(offers_.front());
        offers_.erase(offers_.begin());
        return offer_result(offer, fds);
    }

    static nlohmann::json plain_result() {
        return {{"version", 2},
                {"slots", 64},
                {"size", base::ring_bytes(64)},
                {"published", 0},
                {"descriptors", 0}};
    }

    static nlohmann::json offer_result(const Offer& offer, std::vector<int>& fds) {
        auto result = plain_result();
        result["descriptors"] = 2;
        if (offer.block != nullptr) {
            result["slots"] = offer.block->slots();
            result["size"] = offer.block->size();
            fds = {offer.block->fd(), offer.block->wake_fd()};
        }
        if (offer.fds) {
            fds = *offer.fds;
        }
        if (offer.result.is_object()) {
            result.update(offer.result);
        }
        return result;
    }

    // Caller holds mutex_. The descriptors go with the line's first byte.
    void send_line(const std::string& line, const std::vector<int>& fds) {
        if (client_ >= 0) {
            [[maybe_unused]] const auto n =
                base::send_with_descriptors(client_, line.data(), line.size(), fds);
        }
    }

    std::string dir_;
    std::string path_;
    int listener_ = -1;
    int client_ = -1;
    std::atomic<bool> stopping_{false};
    std::mutex mutex_;
    std::vector<Offer> offers_;
    std::vector<std::pair<nlohmann::json, Offer>> held_;  // request id, its late answer
    nlohmann::json last_subscribe_;
    std::thread thread_;
};

}  // namespace gport::testing
