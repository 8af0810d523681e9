#include "soak_channel.hpp"

#include <sys/mman.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstddef>
#include <deque>
#include <stdexcept>

#include "channel_reply.hpp"
#include "gport/base/attitude_ring.hpp"
#include "gport/base/descriptors.hpp"
#include "gport/base/wake_block.hpp"

namespace gport::bench {
namespace {

constexpr std::int64_t kChannelMs = 1'000'000;
constexpr int kChannelBatch = 32;
constexpr std::size_t kMaxProbeFailures = 20;
constexpr std::size_t kPublishedOffset = offsetof(base::RingHeader, published);
constexpr std::size_t kWakeOffset = offsetof(base::WakeBlock, wake);

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
        ::munmap(const_cast<void*>(wake), base::kWakeBlockBytes);
    }
}

// The previous probe's word moved if samples were published since it opened.
std::string ChannelAttacks::check_last_probe() {
    if (!last_probe_) {
        return "";
    }
    const auto& p = *last_probe_;
    const auto published = reinterpret_cast<const std::atomic<std::uint64_t>*>(
                               static_cast<const char*>(p.ring) + kPublishedOffset)
                               ->load();
    const auto word = reinterpret_cast<const std::atomic<std::uint32_t>*>(
                          static_cast<const char*>(p.wake) + kWakeOffset)
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
    std::deque<int> fds;
    const auto received = read_reply_with_descriptors(fd, fds, std::chrono::seconds(5));
    if (!received) {
        base::close_descriptors(fds);
        return "no reply within 5 s";
    }
    const std::string& line = *received;
    const auto reply = nlohmann::json::parse(line, nullptr, false);
    if (!reply.is_object() || !reply.contains("result") ||
        reply["result"].value("descriptors", 0) != 2 || fds.size() != 2) {
        base::close_descriptors(fds);
        return "reply " + line + " with " + std::to_string(fds.size()) + " descriptor(s)";
    }
    probe->ring_size = reply["result"].value("size", std::size_t{0});
    void* ring = ::mmap(nullptr, probe->ring_size, PROT_READ, MAP_SHARED, fds[0], 0);
    void* wake = ::mmap(nullptr, base::kWakeBlockBytes, PROT_READ, MAP_SHARED, fds[1], 0);
    base::close_descriptors(fds);
    probe->ring = ring == MAP_FAILED ? nullptr : ring;
    probe->wake = wake == MAP_FAILED ? nullptr : wake;
    if (probe->ring == nullptr || probe->wake == nullptr) {
        return "cannot map the blocks";
    }
    probe->published = reinterpret_cast<const std::atomic<std::uint64_t>*>(
                           static_cast<const char*>(probe->ring) + kPublishedOffset)
                           ->load();
    probe->word = reinterpret_cast<const std::atomic<std::uint32_t>*>(
                      static_cast<const char*>(probe->wake) + kWakeOffset)
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

// (g) Batches of 32 attitude_channel, never read. A batch goes out whole:
// what the socket did not take of it is sent first next round, before any
// new batch (never half a line then another); a new batch the socket takes
// nothing of is refused by back-pressure, as it should be. A connection
// gportd closed is replaced.
void ChannelAttacks::hoard(std::int64_t) {
    hoarders_.resize(static_cast<std::size_t>(o_.hoarders));
    static const std::string line = channel_batch_line();
    ++hoard_rounds_;
    std::size_t open = 0;
    for (auto& h : hoarders_) {
        if (!h.fd.valid() && !connect_hoarder(h)) {
            continue;  // gportd full, or gone: next round
        }
        const bool fresh = h.pending.empty();
        if (fresh) {
            h.pending = line;
        }
        const auto sent =
            ::send(h.fd.get(), h.pending.data(), h.pending.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
        if (sent < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) {
            h.fd.reset();  // gportd closed it (EPIPE, ECONNRESET): replaced next round
            ++hoarders_closed_;
            continue;
        }
        ++open;
        h.pending.erase(0, sent > 0 ? static_cast<std::size_t>(sent) : 0);
        if (h.pending.empty()) {
            ++batches_;
        } else if (fresh && sent <= 0) {
            h.pending.clear();
            ++hoard_refused_;
        }
    }
    if (open == 0 && !hoarders_.empty()) {
        ++hoard_rounds_idle_;
    }
}

bool ChannelAttacks::connect_hoarder(Hoarder& h) {
    try {
        h.fd = connect_unix(o_.socket);
        h.pending.clear();
        return true;
    } catch (const std::runtime_error& e) {
        hoard_error_ = e.what();
        return false;
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
    if (hoard_rounds_idle_ > 0) {
        out.push_back(
            "descriptor hoarding stopped: no hoarder connection open in " +
            std::to_string(hoard_rounds_idle_) + " of " + std::to_string(hoard_rounds_) +
            " round(s); last connect error: " + (hoard_error_.empty() ? "none" : hoard_error_));
    } else if (hoard_rounds_ > 0 && o_.hoarders > 0 && batches_ == 0) {
        out.push_back("descriptor hoarding never got a batch out in " +
                      std::to_string(hoard_rounds_) + " round(s)");
    }
    return out;
}

nlohmann::json ChannelAttacks::figures() const {
    return {{"parked_threads", 2 * o_.park_threads},
            {"parking_peers", parkers_started_},
            {"hoarders", o_.hoarders},
            {"hoard_batches_written", batches_},
            {"hoard_batches_refused_by_back_pressure", hoard_refused_},
            {"hoarders_closed_by_gportd_and_replaced", hoarders_closed_},
            {"hoard_rounds_without_a_connection", hoard_rounds_idle_},
            {"channel_probes", probes_},
            {"channel_probes_ok", probes_ok_}};
}

}  // namespace gport::bench
