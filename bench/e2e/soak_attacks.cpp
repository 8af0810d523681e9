#include "soak_attacks.hpp"

#include <fmt/format.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <optional>
#include <stdexcept>

namespace gport::bench {
namespace {

using nlohmann::json;

constexpr int kBurstSpeeds = 96;
constexpr int kBatchSize = 32;
constexpr std::int64_t kMs = 1'000'000;
constexpr std::int64_t kFloodPatience = 20'000 * kMs;
constexpr std::int64_t kBurstPatience = 5'000 * kMs;

bool open_conn(Conn& c, const std::string& socket, std::int64_t t_ns) {
    try {
        c.fd = connect_unix(socket);
    } catch (const std::runtime_error&) {
        return false;  // the daemon may be full: try again later
    }
    c.pending.clear();
    c.opened_ns = t_ns;
    c.expected = 0;
    c.codes.clear();
    return true;
}

// Reads what arrived and hands over each complete line; false once the
// daemon closed the connection.
template <typename OnLine>
bool read_lines(Conn& c, OnLine on_line) {
    char buffer[65536];
    for (;;) {
        const auto n = ::read(c.fd.get(), buffer, sizeof(buffer));
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n < 0 && errno == EAGAIN) {
            break;
        }
        if (n <= 0) {
            return false;
        }
        c.pending.append(buffer, static_cast<std::size_t>(n));
    }
    for (auto nl = c.pending.find('\n'); nl != std::string::npos; nl = c.pending.find('\n')) {
        on_line(c.pending.substr(0, nl));
        c.pending.erase(0, nl + 1);
    }
    return true;
}

// 0 for a result, else the JSON-RPC error code; nothing for a notification.
std::optional<int> reply_code(const json& line) {
    if (!line.is_object() || !line.contains("id")) {
        return std::nullopt;
    }
    return line.contains("error") ? line["error"].value("code", -1) : 0;
}

bool is_in(const std::vector<Conn>& conns, const Conn* c) {
    return !conns.empty() && c >= conns.data() && c < conns.data() + conns.size();
}

std::string batch_line() {
    json batch = json::array();
    for (int i = 0; i < kBatchSize; ++i) {
        batch.push_back({{"jsonrpc", "2.0"}, {"id", i + 1}, {"method", "status"}});
    }
    return batch.dump() + "\n";
}

}  // namespace

void Attacks::act(std::int64_t t_ns) {
    now_ns_ = t_ns;
    if (next_hup_ns_ == 0) {  // the first call: stagger the attacks
        next_burst_ns_ = t_ns + 700 * kMs;
        next_batch_ns_ = t_ns + 300 * kMs;
        next_hup_ns_ = t_ns + o_.sighup_every_ms * kMs;
        hoard_.resize(static_cast<std::size_t>(std::max(o_.hoarders, 0)));
        batchers_.resize(static_cast<std::size_t>(std::max(o_.batch_clients, 0)));
        unsent_.resize(batchers_.size());
    }
    if (t_ns >= next_burst_ns_) {
        start_burst(t_ns);
        next_burst_ns_ = t_ns + o_.burst_every_ms * kMs;
    }
    if (!flood_.empty() && t_ns - flood_started_ns_ > kFloodPatience) {
        end_flood();
    }
    if (t_ns >= next_batch_ns_) {
        feed_batches(t_ns);
        next_batch_ns_ = t_ns + 200 * kMs;
    }
    keep_hoarding(t_ns);
    if (o_.sighup_every_ms > 0 && t_ns >= next_hup_ns_) {
        ::kill(o_.pid, SIGHUP);
        ++hups_;
        next_hup_ns_ = t_ns + o_.sighup_every_ms * kMs;
    }
}

// (a) One write: 96 speeds (each lasting 60 s, so only a stop or another
// command ends the motion), then the stop.
void Attacks::start_burst(std::int64_t t_ns) {
    if (!bursts_.empty() && !bursts_.back().answered &&
        t_ns - bursts_.back().sent_ns < kBurstPatience) {
        return;  // the last burst's stop is still unanswered
    }
    if (!burst_.fd.valid() && !open_conn(burst_, o_.socket, t_ns)) {
        return;
    }
    Burst b;
    b.marker = static_cast<int>(bursts_.size() % 300) + 1;
    b.sent_ns = t_ns;
    std::string text;
    for (int i = 0; i < kBurstSpeeds; ++i) {
        text += fmt::format(
            R"({{"id":{},"method":"speed","params":{{"roll":3,"pitch":-3,"yaw":{},"duration_ms":60000}}}})"
            "\n",
            b.marker * 1000 + i, b.marker);
    }
    text += fmt::format(R"({{"id":{},"method":"stop"}})"
                        "\n",
                        b.marker * 1000 + 999);
    if (!write_all(burst_.fd.get(), text, 1000)) {
        burst_.fd.reset();
        b.answered = true;
        b.stop_code = -1;
        b.stop_message = "the burst could not be sent";
    }
    bursts_.push_back(std::move(b));
}

void Attacks::on_burst_line(const std::string& line) {
    const auto reply = json::parse(line, nullptr, false);
    if (bursts_.empty() || !reply.is_object() ||
        reply.value("id", 0) != bursts_.back().marker * 1000 + 999) {
        return;
    }
    auto& b = bursts_.back();
    b.answered = true;
    b.stop_code = *reply_code(reply);
    if (b.stop_code != 0) {
        b.stop_message = reply["error"].value("message", "");
    }
}

void Attacks::on_link(const std::string& state, std::int64_t t_ns) {
    if (state == "stale" && flood_.empty()) {
        start_flood(t_ns);
    }
}

// (b) Many clients, each pipelining get_settings in one write, while the
// gimbal is silent: every request would wait for it.
void Attacks::start_flood(std::int64_t t_ns) {
    std::string text;
    for (int i = 0; i < o_.flood_depth; ++i) {
        text += fmt::format(R"({{"id":{},"method":"get_settings"}})"
                            "\n",
                            i + 1);
    }
    flood_.resize(static_cast<std::size_t>(o_.flood_clients));
    for (auto& c : flood_) {
        if (open_conn(c, o_.socket, t_ns) && write_all(c.fd.get(), text, 200)) {
            c.expected = o_.flood_depth;
        }
    }
    flood_started_ns_ = t_ns;
    ++floods_;
}

void Attacks::end_flood() {
    int wave = 0;
    for (auto& c : flood_) {
        const int reached = c.codes[0] + c.codes[-32002];  // went to the gimbal
        max_per_client_ = std::max(max_per_client_, reached);
        wave += reached;
        for (const auto& [code, n] : c.codes) {
            flood_codes_[code] += static_cast<std::uint64_t>(n);
        }
        flood_codes_[-1] += static_cast<std::uint64_t>(std::max(c.expected, 0));  // no reply
    }
    max_per_wave_ = std::max(max_per_wave_, wave);
    flood_.clear();
}

// (c) Status batches written, never a reply read: the daemon must stop
// reading this client (or drop it), not buffer without end.
void Attacks::feed_batches(std::int64_t t_ns) {
    static const std::string batch = batch_line();
    for (std::size_t i = 0; i < batchers_.size(); ++i) {
        auto& c = batchers_[i];
        if (!c.fd.valid() && !open_conn(c, o_.socket, t_ns)) {
            continue;
        }
        if (unsent_[i].empty()) {
            unsent_[i] = batch;
        }
        const auto n =
            ::send(c.fd.get(), unsent_[i].data(), unsent_[i].size(), MSG_NOSIGNAL | MSG_DONTWAIT);
        if (n > 0) {
            unsent_[i].erase(0, static_cast<std::size_t>(n));
            batches_written_ += unsent_[i].empty() ? 1 : 0;
        } else if (n < 0 && errno != EAGAIN && errno != EINTR) {
            ++batchers_closed_;  // the daemon gave up on it
            c.fd.reset();
            unsent_[i].clear();
        }
    }
}

// (d) Connections that say nothing. A closed one is reopened a second later.
void Attacks::keep_hoarding(std::int64_t t_ns) {
    for (auto& c : hoard_) {
        if (c.fd.valid()) {
            max_hoard_age_ns_ = std::max(max_hoard_age_ns_, t_ns - c.opened_ns);
        } else if (t_ns >= c.opened_ns) {  // opened_ns: not before, while closed
            open_conn(c, o_.socket, t_ns);
        }
    }
}

void Attacks::append_pollfds(std::vector<pollfd>& fds) {
    polled_.clear();
    const auto add = [&](Conn& c) {
        if (c.fd.valid()) {
            fds.push_back({c.fd.get(), POLLIN, 0});
            polled_.push_back(&c);
        }
    };
    add(burst_);
    std::for_each(flood_.begin(), flood_.end(), add);
    std::for_each(hoard_.begin(), hoard_.end(), add);
}

void Attacks::on_polled(const pollfd* fds, std::size_t count, std::int64_t t_ns) {
    for (std::size_t i = 0; i < count && i < polled_.size(); ++i) {
        if (fds[i].revents == 0) {
            continue;
        }
        Conn& c = *polled_[i];
        bool open_still = true;
        if (&c == &burst_) {
            open_still = read_lines(c, [this](const std::string& l) { on_burst_line(l); });
        } else if (is_in(flood_, &c)) {
            open_still = read_lines(c, [&c](const std::string& l) {
                if (const auto code = reply_code(json::parse(l, nullptr, false))) {
                    ++c.codes[*code];
                    --c.expected;
                }
            });
        } else {  // a hoarder: whatever it is told, it has said nothing
            open_still = read_lines(c, [](const std::string&) {});
            if (!open_still) {
                ++hoarders_closed_;
                c.opened_ns = t_ns + 1000 * kMs;
            }
        }
        if (!open_still) {
            c.fd.reset();
        }
    }
    if (!flood_.empty() &&
        std::all_of(flood_.begin(), flood_.end(), [](const Conn& c) { return c.expected <= 0; })) {
        end_flood();
    }
}

void Attacks::finish() {
    if (!flood_.empty()) {
        end_flood();
    }
    burst_.fd.reset();
    for (auto& c : batchers_) {
        c.fd.reset();
    }
    for (auto& c : hoard_) {
        c.fd.reset();  // the vector stays: problems() and figures() count it
    }
}

}  // namespace gport::bench
