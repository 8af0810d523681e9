// The server's limits: who may take a slot, what happens when descriptors
// run out, and the memory all sessions may hold together.
#include <fmt/format.h>
#include <malloc.h>
#include <sys/resource.h>

#include <algorithm>
#include <boost/asio/write.hpp>

#include "gport/ipc/server.hpp"
#include "session.hpp"

namespace gport::ipc {
namespace {

namespace asio = boost::asio;
using stream_protocol = asio::local::stream_protocol;
using Clock = std::chrono::steady_clock;

// Descriptors the daemon needs besides its clients: stdio, the serial port,
// the simulator's pty pair, the listening socket, epoll, timers, signals,
// the journal, and a client being refused.
constexpr std::size_t kOtherDescriptors = 32;
// A client's socket and, for a while, its attitude channel's wake block.
constexpr std::size_t kDescriptorsPerClient = 2;
// How long accepting pauses when descriptors run out: long enough not to
// spin, short enough that a freed slot is used soon.
constexpr auto kAcceptPause = std::chrono::milliseconds(250);
// Accept failures are logged at most this often (first one at once).
constexpr auto kAcceptLogInterval = std::chrono::seconds(60);
// Returning freed heap to the system: after a spike of at least this many
// queued bytes, once the total has fallen to a quarter, at most once a second.
constexpr std::size_t kTrimAfterPeak = 1024 * 1024;
constexpr auto kTrimInterval = std::chrono::seconds(1);
// ... or after this many sessions closed (each held buffers of its own).
constexpr std::size_t kTrimAfterClosed = 8;

// A summary is due for the first event, then at most once per interval.
bool due(Clock::time_point last, Clock::time_point now) {
    return last == Clock::time_point{} || now - last >= kAcceptLogInterval;
}

}  // namespace

// Each client costs up to two descriptors: its socket, and the wake block of
// its attitude channel from its first attitude_channel request until that
// reply went out (gportd then closes its copy and keeps the mapping). Make
// sure max_clients of them fit under RLIMIT_NOFILE, raising the soft limit
// up to the hard one if needed, or serve fewer clients (with a warning)
// rather than fail at accept. Descriptors in flight (SCM_RIGHTS) count
// against the same limit: at most two per client, so they fit too.
void Server::fit_descriptor_limit() {
    rlimit limit{};
    if (::getrlimit(RLIMIT_NOFILE, &limit) != 0) {
        return;
    }
    const rlim_t needed = kDescriptorsPerClient * config_.max_clients + kOtherDescriptors;
    if (limit.rlim_cur != RLIM_INFINITY && limit.rlim_cur < needed) {
        rlimit raised = limit;
        raised.rlim_cur =
            limit.rlim_max == RLIM_INFINITY ? needed : std::min(needed, limit.rlim_max);
        if (::setrlimit(RLIMIT_NOFILE, &raised) == 0) {
            limit = raised;
        }
    }
    if (limit.rlim_cur == RLIM_INFINITY || limit.rlim_cur >= needed) {
        return;
    }
    const auto fit = limit.rlim_cur > kOtherDescriptors + kDescriptorsPerClient
                         ? (limit.rlim_cur - kOtherDescriptors) / kDescriptorsPerClient
                         : 1;
    max_clients_ = std::min<std::size_t>(config_.max_clients, fit);
    log_->warn(
        "socket.max_clients is {} but the open-file limit (RLIMIT_NOFILE) is {} (hard {}); "
        "serving at most {} clients",
        config_.max_clients, limit.rlim_cur, limit.rlim_max, max_clients_);
}

// Out of descriptors (EMFILE/ENFILE), accept fails at once, again and again:
// pause instead of spinning, and log a summary instead of every failure.
void Server::on_accept_error(const boost::system::error_code& error) {
    ++accept_failures_;
    const auto now = Clock::now();
    if (due(accept_logged_, now)) {
        log_->warn("accepting clients failed {} time(s) since the last report: {}; pausing {} ms",
                   accept_failures_, error.message(), kAcceptPause.count());
        accept_failures_ = 0;
        accept_logged_ = now;
    }
    accept_pause_.expires_after(kAcceptPause);
    accept_pause_.async_wait([this](const boost::system::error_code& e) {
        if (!e && !closed_) {
            accept();
        }
    });
}

// Why a client may not have a slot, or nothing when it may. The last
// reserved_command_slots slots go only to peers allowed to command, so
// read-only peers cannot lock them out; no uid takes more than
// max_clients_per_uid.
std::optional<std::string> Server::admission(const daemon::ClientInfo& client, bool& asked_core) {
    const std::size_t total = clients();
    if (total >= max_clients_) {
        return fmt::format("too many clients ({})", max_clients_);
    }
    const auto same_uid = static_cast<std::size_t>(
        std::count_if(sessions_.begin(), sessions_.end(), [&](const auto& entry) {
            return !entry.second->closed() && entry.second->info().uid == client.uid;
        }));
    if (same_uid >= config_.max_clients_per_uid) {
        return fmt::format("too many clients for uid {} ({}, socket.max_clients_per_uid)",
                           client.uid, config_.max_clients_per_uid);
    }
    const std::size_t reserved = std::min(config_.reserved_command_slots, max_clients_ - 1);
    if (total >= max_clients_ - reserved) {
        asked_core = true;
        if (!api_.may_command(client)) {
            return fmt::format(
                "too many clients: the last {} of {} slots are reserved for peers allowed to "
                "command (socket.reserved_command_slots)",
                reserved, max_clients_);
        }
    }
    return std::nullopt;
}

// The refused client hears why, then is closed.
void Server::reject(stream_protocol::socket socket, const std::string& why) {
    ++refused_;
    const auto now = Clock::now();
    if (due(refused_logged_, now)) {
        log_->warn("refused {} client(s) since the last report; the latest: {}", refused_, why);
        refused_ = 0;
        refused_logged_ = now;
    }
    auto line = std::make_shared<const std::string>(error_line(rpc_error::kNoSlot, why));
    auto peer = std::make_shared<stream_protocol::socket>(std::move(socket));
    asio::async_write(*peer, asio::buffer(*line),
                      [peer, line](const boost::system::error_code&, std::size_t) {
                          boost::system::error_code ignored;
                          peer->shutdown(stream_protocol::socket::shutdown_both, ignored);
                          peer->close(ignored);
                      });
}

void Server::account(std::size_t before, std::size_t after) {
    queued_bytes_ = queued_bytes_ - before + after;
    queued_peak_ = std::max(queued_peak_, queued_bytes_);
    if (after < before) {
        trim_memory();
    }
}

// glibc keeps freed heap for reuse; after a spike (many clients' queues, a
// burst of big batches, many sessions gone) give it back so RSS returns to
// its usual size.
void Server::trim_memory() {
    const bool spike_over = queued_peak_ >= kTrimAfterPeak && queued_bytes_ <= queued_peak_ / 4;
    if (!spike_over && closed_since_trim_ < kTrimAfterClosed) {
        return;
    }
    const auto now = Clock::now();
    if (now - last_trim_ < kTrimInterval) {
        // Due, but too soon: trim once the interval is over, or a burst of
        // closes would leave everything after its first few untrimmed.
        if (!trim_armed_ && !closed_) {
            trim_armed_ = true;
            trim_timer_.expires_at(last_trim_ + kTrimInterval);
            trim_timer_.async_wait([this](const boost::system::error_code& error) {
                trim_armed_ = false;
                if (!error) {
                    trim_memory();
                }
            });
        }
        return;
    }
    last_trim_ = now;
    queued_peak_ = queued_bytes_;
    closed_since_trim_ = 0;
    ::malloc_trim(0);
}

}  // namespace gport::ipc
