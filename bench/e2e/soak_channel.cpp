#include "soak_channel.hpp"

#include <sys/mman.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <deque>
#include <stdexcept>

#include "gport/base/descriptors.hpp"

namespace gport::bench {
namespace {

constexpr std::int64_t kChannelMs = 1'000'000;
constexpr int kChannelBatch = 32;
constexpr std::size_t kMaxProbeFailures = 20;

std::string channel_batch_line() {
    std::string line = "[";
    for (int i = 1; i <= kChannelBatch; ++i) {
        line += i > 1 ? "," : "";
        line += R"({"jsonrpc":"2.0","id":)";
        line += std::to_string(i);
        line += R"(,"method":"attitude_channel"})";
    }
    return line + "]\n";
}

}  // namespace

ChannelAttacks::~ChannelAttacks() {
    finish();
}

ChannelAttacks::Probe::~Probe() {
    if (ring != nullptr) {
        ::munmap(const_cast<void*>(ring), ring_size);
    }
    if (wake != nullptr) {
        ::munmap(const_cast<void*>(wake), 64);
    }
}

// The previous probe's word moved if samples were published since it opened.
std::string ChannelAttacks::check_last_probe() {
    if (!last_probe_) {
        return "";
    }
    const auto& p = *last_probe_;
    const auto published =
        reinterpret_cast<const std::atomic<std::uint64_t>*>(static_cast<const char*>(p.ring) + 32)
            ->load();
    const auto word =
        reinterpret_cast<const std::atomic<std::uint32_t>*>(static_cast<const char*>(p.wake) + 16)
            ->load();
    if (published != p.published && word == p.word) {
        return std::to_string(published - p.published) +
               " samples published, its wake word never bumped";
    }
    return "";
}

// One attitude_channel on a fresh connection, kept open until the next
// probe: "" when it got both descriptors and could map them.
std::string ChannelAttacks::open_probe() {
    auto probe = std::make_unique<Probe>();
    probe->connection = connect_unix(o_.socket);
    const int fd = probe->connection.get();
    if (!write_all(fd, R"({"jsonrpc":"2.0","id":1,"method":"attitude_channel"})"
                       "\n")) {
        return "cannot send";
    }
    std::string text;
    std::deque<int> fds;
    const auto deadline = now_ns() + 5000 * kChannelMs;
    while (text.find('\n') == std::string::npos) {
        char data[4096];
        const auto n = base::receive_with_descriptors(fd, data, sizeof(data), fds);
        if (n < 0 && (errno == EAGAIN || errno == EINTR) && now_ns() < deadline) {
            ::usleep(500);
            continue;
        }
        if (n <= 0) {
            base::close_descriptors(fds);
            return "no reply within 5 s";
        }
        text.append(data, static_cast<std::size_t>(n));
    }
    const auto line = text.substr(0, text.find('\n'));
    const auto reply = nlohmann::json::parse(line, nullptr, false);
    if (!reply.is_object() || !reply.contains("result") ||
        reply["result"].value("descriptors", 0) != 2 || fds.size() != 2) {
        base::close_descriptors(fds);
        return "reply " + line + " with " + std::to_string(fds.size()) + " descriptor(s)";
    }
    probe->ring_size = reply["result"].value("size", std::size_t{0});
    void* ring = ::mmap(nullptr, probe->ring_size, PROT_READ, MAP_SHARED, fds[0], 0);
    void* wake = ::mmap(nullptr, 64, PROT_READ, MAP_SHARED, fds[1], 0);
    base::close_descriptors(fds);
    probe->ring = ring == MAP_FAILED ? nullptr : ring;
    probe->wake = wake == MAP_FAILED ? nullptr : wake;
    if (probe->ring == nullptr || probe->wake == nullptr) {
        return "cannot map the blocks";
    }
    probe->published = reinterpret_cast<const std::atomic<std::uint64_t>*>(
                           static_cast<const char*>(probe->ring) + 32)
                           ->load();
    probe->word = reinterpret_cast<const std::atomic<std::uint32_t>*>(
                      static_cast<const char*>(probe->wake) + 16)
                      ->load();
    last_probe_ = std::move(probe);
    return "";
}

void ChannelAttacks::act(std::int64_t t_ns) {
    if (!started_) {
        start(t_ns);
    }
    if (t_ns >= next_hoard_ns_) {
        hoard(t_ns);
        next_hoard_ns_ = t_ns + 200 * kChannelMs;
    }
    if (t_ns >= next_probe_ns_) {
        probe();
        next_probe_ns_ = now_ns() + o_.probe_every_ms * kChannelMs;
    }
}

void ChannelAttacks::start(std::int64_t t_ns) {
    started_ = true;
    next_hoard_ns_ = t_ns + 500 * kChannelMs;
    next_probe_ns_ = t_ns + 1500 * kChannelMs;
    try {
        parkers_.push_back(std::make_unique<ParkAttack>(o_.socket, o_.park_threads, false));
        parkers_.push_back(std::make_unique<ParkAttack>(o_.socket, o_.park_threads, true));
        parkers_started_ = parkers_.size();
    } catch (const std::exception& e) {
        park_error_ = e.what();
    }
}

// (g) Batches of 32 attitude_channel, never read; a connection the daemon
// closed (or that it stopped reading) is replaced.
void ChannelAttacks::hoard(std::int64_t) {
    hoarders_.resize(static_cast<std::size_t>(o_.hoarders));
    static const std::string line = channel_batch_line();
    for (auto& fd : hoarders_) {
        if (!fd.valid()) {
            try {
                fd = connect_unix(o_.socket);
            } catch (const std::runtime_error&) {
                continue;  // full: later
            }
        }
        if (write_all(fd.get(), line, 0)) {
            ++batches_;
        } else {
            ++hoard_refused_;  // its socket is full: back-pressure, as it should be
        }
    }
}

void ChannelAttacks::probe() {
    ++probes_;
    std::string failure = check_last_probe();
    last_probe_.reset();
    try {
        if (failure.empty()) {
            failure = open_probe();
        }
    } catch (const std::exception& e) {
        failure = e.what();
    }
    if (failure.empty()) {
        ++probes_ok_;
    } else if (probe_failures_.size() < kMaxProbeFailures) {
        probe_failures_.push_back(failure);
    }
}

void ChannelAttacks::finish() {
    last_probe_.reset();
    parkers_.clear();
    hoarders_.clear();
}

std::vector<std::string> ChannelAttacks::problems() const {
    std::vector<std::string> out;
    if (!park_error_.empty()) {
        out.push_back("futex-waiter attack did not start: " + park_error_);
    }
    for (const auto& failure : probe_failures_) {
        out.push_back("attitude_channel probe: " + failure);
    }
    if (probes_ == 0) {
        out.push_back("no attitude_channel probe ran");
    }
    return out;
}

nlohmann::json ChannelAttacks::figures() const {
    return {{"parked_threads", 2 * o_.park_threads},
            {"parking_peers", parkers_started_},
            {"hoarders", o_.hoarders},
            {"hoard_batches_written", batches_},
            {"hoard_batches_refused_by_back_pressure", hoard_refused_},
            {"channel_probes", probes_},
            {"channel_probes_ok", probes_ok_}};
}

}  // namespace gport::bench
