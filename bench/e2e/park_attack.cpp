#include "park_attack.hpp"

#include <fcntl.h>
#include <pthread.h>
#include <sys/mman.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <vector>

#include "channel_reply.hpp"
#include "gport/base/attitude_ring.hpp"
#include "gport/base/descriptors.hpp"
#include "gport/base/futex.hpp"
#include "gport/base/wake_block.hpp"

extern char** environ;

namespace gport::bench {
namespace {

constexpr std::string_view kParkOpen = R"({"jsonrpc":"2.0","id":1,"method":"attitude_channel"})"
                                       "\n";
// The word gportd wakes: version 1 had it in the ring header (now reserved).
constexpr std::size_t kVersion1WordOffset = offsetof(base::RingHeader, reserved_wake);
constexpr std::size_t kWakeWordOffset = offsetof(base::WakeBlock, wake);  // version 2
constexpr std::size_t kStack = 64 * 1024;  // thousands of threads: small stacks

struct ParkChannel {
    nlohmann::json result;
    std::deque<int> fds;
};

// Sends attitude_channel on `socket` and reads the reply and its descriptors.
ParkChannel ask_channel(int socket) {
    if (!write_all(socket, kParkOpen)) {
        throw std::runtime_error("park: cannot send attitude_channel");
    }
    ParkChannel c;
    const auto line = read_reply_with_descriptors(socket, c.fds, std::chrono::seconds(10));
    if (!line) {
        base::close_descriptors(c.fds);
        throw std::runtime_error("park: no reply to attitude_channel within 10 s");
    }
    const auto reply = nlohmann::json::parse(*line);
    if (!reply.contains("result")) {
        base::close_descriptors(c.fds);
        throw std::runtime_error("park: attitude_channel refused: " + reply.dump());
    }
    c.result = reply["result"];
    return c;
}

const std::atomic<std::uint32_t>* word_of(int fd, std::size_t size, std::size_t offset) {
    void* memory = ::mmap(nullptr, size, PROT_READ, MAP_SHARED, fd, 0);
    if (memory == MAP_FAILED) {
        throw std::runtime_error(std::string("park: mmap: ") + std::strerror(errno));
    }
    return reinterpret_cast<const std::atomic<std::uint32_t>*>(static_cast<char*>(memory) + offset);
}

// `keys` words of a shared-memory block of the peer's own (a memfd, as
// gportd's blocks are, so the futexes are shared ones keyed by inode and
// offset and hash into the kernel's one global table with gportd's wake
// words): spread over that many keys, the parked threads sit in every hash
// bucket, the one of the connection's wake word too, whatever the hash.
std::atomic<std::uint32_t>* cover_words(int keys) {
    const auto bytes = static_cast<std::size_t>(keys) * sizeof(std::uint32_t);
    Fd block(::memfd_create("gport-park-keys", MFD_CLOEXEC));
    if (!block.valid() || ::ftruncate(block.get(), static_cast<off_t>(bytes)) != 0) {
        throw std::runtime_error(std::string("park: memfd for the keys: ") + std::strerror(errno));
    }
    void* memory = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED, block.get(), 0);
    if (memory == MAP_FAILED) {
        throw std::runtime_error(std::string("park: mmap of the keys: ") + std::strerror(errno));
    }
    return static_cast<std::atomic<std::uint32_t>*>(memory);
}

void* park_thread(void* word) {
    const auto& w = *static_cast<const std::atomic<std::uint32_t>*>(word);
    for (;;) {
        base::futex_wait(w, w.load(std::memory_order_acquire), std::chrono::seconds(60));
    }
    return nullptr;
}

}  // namespace

int park_child_main(int argc, char** argv) {
    if (argc < 5) {
        return 64;
    }
    const std::string socket = argv[0];
    const int threads = std::atoi(argv[1]);
    const bool gone = std::atoi(argv[2]) != 0;
    const int report = std::atoi(argv[3]);
    const int keys = std::atoi(argv[4]);
    try {
        Fd connection = connect_unix(socket);
        auto channel = ask_channel(connection.get());
        const int version = channel.result.value("version", 0);
        const auto size = channel.result.at("size").get<std::size_t>();
        const int ring = base::take_descriptor(channel.fds);
        const int wake = base::take_descriptor(channel.fds);
        const auto* word = version >= 2 ? word_of(wake, base::kWakeBlockBytes, kWakeWordOffset)
                                        : word_of(ring, size, kVersion1WordOffset);
        auto* covers = keys > 0 ? cover_words(keys) : nullptr;
        pthread_attr_t attr;
        ::pthread_attr_init(&attr);
        ::pthread_attr_setstacksize(&attr, kStack);
        for (int i = 0; i < threads; ++i) {
            const auto* target = covers != nullptr ? &covers[i % keys] : word;
            pthread_t thread;
            if (::pthread_create(&thread, &attr, park_thread,
                                 const_cast<std::atomic<std::uint32_t>*>(target)) != 0) {
                throw std::runtime_error("park: pthread_create failed after " + std::to_string(i) +
                                         " threads");
            }
        }
        ::usleep(200'000);  // let the last ones reach FUTEX_WAIT
        if (gone) {
            connection.reset();  // disconnects; the threads stay parked on the mapping
        }
        const std::string line = "parked " + std::to_string(version) + "\n";
        [[maybe_unused]] const auto n = ::write(report, line.data(), line.size());  // a pipe
        ::close(report);
        for (;;) {
            ::pause();
        }
    } catch (const std::exception& e) {
        const std::string line = std::string("error ") + e.what() + "\n";
        [[maybe_unused]] const auto n = ::write(report, line.data(), line.size());
        return 1;
    }
}

ParkAttack::ParkAttack(const std::string& socket, int threads, bool gone, int keys)
    : threads_(threads), gone_(gone), keys_(keys) {
    auto child = spawn_self({"bench_e2e", "--park-child", socket, std::to_string(threads),
                             gone ? "1" : "0", "3", std::to_string(keys)},
                            "park: the peer");
    child_ = std::move(child);
    std::string pending;
    std::string line;
    if (!read_line(child_->report(), pending, line, 120'000) || line.rfind("parked ", 0) != 0) {
        stop();
        throw std::runtime_error("park: the peer did not park its threads: " + line);
    }
    version_ = std::atoi(line.c_str() + 7);
    if (gone) {
        holder_ = connect_unix(socket);
        auto channel = ask_channel(holder_.get());
        base::close_descriptors(channel.fds);
    }
}

ParkAttack::~ParkAttack() {
    stop();
}

void ParkAttack::stop() {
    child_.reset();  // SIGKILL, and reaped
    holder_.reset();
}

}  // namespace gport::bench
