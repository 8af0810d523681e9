#include "shm_readers.hpp"

#include <sys/mman.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <deque>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "fake_gimbal.hpp"
#include "gport/base/attitude_ring.hpp"
#include "gport/base/descriptors.hpp"
#include "gport/base/futex.hpp"
#include "gport/base/wake_block.hpp"

namespace gport::bench {
namespace {

constexpr std::string_view kOpen = R"({"jsonrpc":"2.0","id":1,"method":"attitude_channel"})"
                                   "\n";

// The counter the fake gimbal put in the IMU roll and pitch (fake_gimbal.hpp).
std::uint32_t counter_of(const base::RingSample& sample) {
    if (sample.imu[0] < 0 || sample.imu[1] < 0) {
        return 0;
    }
    return static_cast<std::uint32_t>(std::lround(sample.imu[0] * 100)) +
           kCounterBase * static_cast<std::uint32_t>(std::lround(sample.imu[1] * 100));
}

struct Received {
    Fd ring;
    Fd wake;
    std::size_t size = 0;
};

// Reads the reply line to attitude_channel with recvmsg; returns the two
// descriptors that came with it (the ring, the connection's wake block)
// and the ring's size.
Received receive_channel(int socket) {
    std::string text;
    std::deque<int> received;  // gportd sends two, with a connection's first reply
    const auto deadline = now_ns() + 10'000'000'000LL;
    while (text.find('\n') == std::string::npos) {
        if (now_ns() > deadline) {
            throw std::runtime_error("attitude_channel: no reply within 10 s");
        }
        char data[4096];
        const auto n = base::receive_with_descriptors(socket, data, sizeof(data), received);
        if (n < 0 && (errno == EAGAIN || errno == EINTR)) {
            ::usleep(1000);
            continue;
        }
        if (n <= 0) {
            throw std::runtime_error("attitude_channel: the connection closed");
        }
        text.append(data, static_cast<std::size_t>(n));
    }
    Received r;
    r.ring.reset(base::take_descriptor(received));
    r.wake.reset(base::take_descriptor(received));
    base::close_descriptors(received);
    const auto reply = nlohmann::json::parse(text.substr(0, text.find('\n')));
    if (!reply.contains("result") || !r.ring.valid() || !r.wake.valid()) {
        throw std::runtime_error("attitude_channel: " + reply.dump());
    }
    r.size = reply["result"]["size"].get<std::size_t>();
    return r;
}

const void* map_read_only(int fd, std::size_t size) {
    void* memory = ::mmap(nullptr, size, PROT_READ, MAP_SHARED, fd, 0);
    if (memory == MAP_FAILED) {
        throw std::runtime_error(std::string("mmap of the attitude channel: ") +
                                 std::strerror(errno));
    }
    return memory;
}

}  // namespace

struct ShmReaders::Reader {
    Fd socket;  // kept open: a reader that disconnects is no longer woken
    const void* memory = nullptr;
    std::size_t size = 0;
    const void* wake = nullptr;  // this connection's wake block
    Subscriber result;           // its reported_dropped counts the samples missed
    std::uint64_t cursor = 0;
    std::uint32_t last = 0;
    std::atomic<std::uint32_t> last_seen{0};  // `last`, for caught_up() on another thread
    std::atomic<std::uint64_t> wakes{0};

    bool owner = true;  // false: it shares another reader's connection and mappings

    ~Reader() {
        if (!owner) {
            return;
        }
        if (memory != nullptr) {
            ::munmap(const_cast<void*>(memory), size);
        }
        if (wake != nullptr) {
            ::munmap(const_cast<void*>(wake), base::kWakeBlockBytes);
        }
    }
};

ShmReaders::ShmReaders(const std::string& socket, int count, std::size_t expected_samples,
                       int threads)
    : thread_count_(threads > 0 && threads < count ? threads : count) {
    for (int i = 0; i < count; ++i) {
        auto reader = std::make_unique<Reader>();
        if (i >= thread_count_) {
            // Readers sharing a thread share its connection, as readers in
            // one process share their Client's channel (one wake block:
            // gportd wakes that process once per sample).
            const Reader& first = *readers_[static_cast<std::size_t>(i % thread_count_)];
            reader->owner = false;
            reader->memory = first.memory;
            reader->size = first.size;
            reader->wake = first.wake;
            reader->result.receipts.reserve(expected_samples + 16);
            readers_.push_back(std::move(reader));
            continue;
        }
        auto connected = connect_unix_retry(socket, 10000);  // gportd may still be starting
        if (!connected) {
            throw std::runtime_error("shm reader: gportd never listened on " + socket);
        }
        reader->socket = std::move(*connected);
        if (!write_all(reader->socket.get(), kOpen)) {
            throw std::runtime_error("shm reader " + std::to_string(i) + ": cannot send");
        }
        const auto received = receive_channel(reader->socket.get());
        reader->memory = map_read_only(received.ring.get(), received.size);
        reader->size = received.size;
        reader->wake = map_read_only(received.wake.get(), base::kWakeBlockBytes);
        if (auto error = base::RingReader::check(reader->memory, reader->size)) {
            throw std::runtime_error("attitude channel: " + *error);
        }
        if (auto error = base::check_wake_block(reader->wake, base::kWakeBlockBytes)) {
            throw std::runtime_error("attitude channel: " + *error);
        }
        reader->result.receipts.reserve(expected_samples + 16);
        readers_.push_back(std::move(reader));
    }
}

ShmReaders::~ShmReaders() {
    stop();
}

void ShmReaders::start() {
    std::vector<std::vector<Reader*>> groups(static_cast<std::size_t>(thread_count_));
    for (std::size_t i = 0; i < readers_.size(); ++i) {
        groups[i % groups.size()].push_back(readers_[i].get());
    }
    for (auto& group : groups) {
        threads_.emplace_back([this, group] { run(group); });
    }
}

void ShmReaders::stop() {
    stop_ = true;
    for (auto& thread : threads_) {
        thread.join();
    }
    threads_.clear();
}

// Takes every new sample of one reader; false once the channel is closed.
bool ShmReaders::take(Reader& reader) {
    const base::RingReader ring(reader.memory, reader.size);
    auto& out = reader.result;
    while (auto sample = ring.next(reader.cursor, out.reported_dropped)) {
        const auto t = now_ns();
        const auto counter = counter_of(*sample);
        out.out_of_order += counter != 0 && counter <= reader.last ? 1 : 0;
        reader.last = counter != 0 ? counter : reader.last;
        out.receipts.push_back({counter, t});
    }
    reader.last_seen.store(reader.last, std::memory_order_relaxed);
    return !ring.closed();
}

// Takes every new sample of its readers, then sleeps on their connection's
// wake word (gportd bumps it per sample and wakes one waiter) until the next.
void ShmReaders::run(const std::vector<Reader*>& readers) {
    const auto& word = base::wake_word(readers.front()->wake);
    while (!stop_.load(std::memory_order_relaxed)) {
        const auto seen = word.load(std::memory_order_acquire);
        bool open = true;
        for (Reader* reader : readers) {
            open = take(*reader) && open;
        }
        if (!open) {
            break;
        }
        if (base::futex_wait(word, seen, std::chrono::milliseconds(100)) ==
            base::FutexWait::kWoken) {
            readers.front()->wakes.fetch_add(1, std::memory_order_relaxed);
        }
    }
}

std::vector<Subscriber> ShmReaders::take_results() {
    std::vector<Subscriber> results;
    for (auto& reader : readers_) {
        results.push_back(std::move(reader->result));
        results.back().subscribed = true;
    }
    return results;
}

bool ShmReaders::caught_up(std::uint32_t last) const {
    return std::all_of(readers_.begin(), readers_.end(), [last](const auto& reader) {
        return reader->last_seen.load(std::memory_order_relaxed) >= last;
    });
}

std::uint64_t ShmReaders::wakes() const {
    std::uint64_t total = 0;
    for (const auto& reader : readers_) {
        total += reader->wakes.load();
    }
    return total;
}

}  // namespace gport::bench
