// gport_soak: the soak test's client side (scripts/soak.sh starts the
// simulator and gportd, then this). A hundred clients subscribe, move the
// gimbal, change settings, stall and disconnect at random while a watcher
// follows `motion` and `link` notifications and samples `status` and the
// daemon's memory once a second. Alongside, the attacks of soak_attacks.hpp
// and the line-rate floods of soak_line_rate.hpp run, and a well-behaved
// subscriber measures its attitude gaps. Prints the figures and PASS or FAIL.
#include <poll.h>
#include <signal.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string_view>
#include <vector>

#include "posix.hpp"
#include "soak_attacks.hpp"
#include "soak_channel.hpp"
#include "soak_checks.hpp"
#include "soak_line_rate.hpp"
#include "soak_probe.hpp"
#include "soak_worker.hpp"

namespace gport::bench {
namespace {

using nlohmann::json;

struct SoakOptions {
    std::string socket;
    pid_t pid = 0;
    double seconds = 600;
    int clients = 100;
    std::uint32_t seed = 1;
    long rss_limit_kib = 32 * 1024;
    long rss_margin_kib = 1024;
    std::string json_path;
    std::string trace_path;  // gport-sim's --trace output, for the burst check
    AttackOptions attacks;
    double max_gap_ms = 500;
    int park_threads = 500;         // per parking peer of the channel attacks (0: none)
    bool channel_attacks = true;    // (f) and (g) and the channel prober
    bool line_rate_attacks = true;  // (h), (i), (j): soak_line_rate.hpp
    LineRateAttackOptions line_rate;
};

std::optional<SoakOptions> parse(int argc, char** argv) {
    SoakOptions o;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string_view arg = argv[i];
        const char* value = argv[i + 1];
        if (arg == "--socket") {
            o.socket = value;
        } else if (arg == "--pid") {
            o.pid = static_cast<pid_t>(std::atol(value));
        } else if (arg == "--seconds") {
            o.seconds = std::atof(value);
        } else if (arg == "--clients") {
            o.clients = std::atoi(value);
        } else if (arg == "--seed") {
            o.seed = static_cast<std::uint32_t>(std::atol(value));
        } else if (arg == "--rss-limit-mib") {
            o.rss_limit_kib = std::atol(value) * 1024;
        } else if (arg == "--rss-margin-kib") {
            o.rss_margin_kib = std::atol(value);
        } else if (arg == "--json") {
            o.json_path = value;
        } else if (arg == "--trace") {
            o.trace_path = value;
        } else if (arg == "--sighup-every-ms") {
            o.attacks.sighup_every_ms = std::atoi(value);
        } else if (arg == "--hoarders") {
            o.attacks.hoarders = std::atoi(value);
        } else if (arg == "--idle-timeout-s") {
            o.attacks.idle_timeout_s = std::atoi(value);
        } else if (arg == "--max-gap-ms") {
            o.max_gap_ms = std::atof(value);
        } else if (arg == "--park-threads") {
            o.park_threads = std::atoi(value);
        } else if (arg == "--channel-attacks") {
            o.channel_attacks = std::atoi(value) != 0;
        } else if (arg == "--line-rate-attacks") {
            o.line_rate_attacks = std::atoi(value) != 0;
        } else if (arg == "--reader-uid") {
            o.line_rate.reader_uid = static_cast<uid_t>(std::atol(value));
        } else {
            std::cerr << "gport_soak: unknown option " << arg << "\n";
            return std::nullopt;
        }
    }
    if (argc % 2 == 0 || o.socket.empty() || o.pid <= 0 || o.seconds < 2 || o.clients < 1) {
        std::cerr << "usage: gport_soak --socket PATH --pid GPORTD_PID [--seconds S (>= 2)]\n"
                     "         [--clients N (>= 1)] [--seed N] [--rss-limit-mib N]\n"
                     "         [--rss-margin-kib N] [--json FILE] [--trace SIM_TRACE]\n"
                     "         [--sighup-every-ms N (0: none)] [--hoarders N]\n"
                     "         [--idle-timeout-s N] [--max-gap-ms N] [--park-threads N]\n"
                     "         [--channel-attacks 0|1] [--line-rate-attacks 0|1]\n"
                     "         [--reader-uid UID (read-only floods; 0: ours)]\n";
        return std::nullopt;
    }
    o.attacks.socket = o.socket;
    o.attacks.pid = o.pid;
    o.line_rate.socket = o.socket;
    return o;
}

// The watcher: notifications of motion and link, and the 1 Hz status.
struct Watcher {
    Fd fd;
    std::string pending;
    std::uint64_t next_id = 1;
    std::map<std::string, std::uint64_t> link_states;
    std::uint64_t max_clients_seen = 0;
};

class Soak {
  public:
    explicit Soak(SoakOptions o)
        : o_(std::move(o)),
          deadman_(1'000'000'000),
          attacks_(o_.attacks),
          channel_attacks_(ChannelAttackOptions{o_.socket, o_.park_threads}),
          line_rate_attacks_(o_.line_rate),
          probe_(o_.socket, o_.max_gap_ms) {}
    int run();

  private:
    void serve(std::int64_t until_ns, bool act);
    void on_watcher_line(const std::string& line, std::int64_t t);
    void sample(std::int64_t t);
    json summary(bool pass) const;
    bool attacks_pass() const;

    SoakOptions o_;
    Watcher watcher_;
    std::vector<Worker> workers_;
    WorkerTally tally_;
    DeadmanCheck deadman_;
    CounterCheck counters_;
    std::vector<long> rss_;
    std::int64_t next_sample_ = 0;
    bool daemon_died_ = false;
    RssVerdict rss_verdict_;
    Attacks attacks_;
    ChannelAttacks channel_attacks_;     // (f) futex waiters, (g) descriptor hoarding
    LineRateAttacks line_rate_attacks_;  // (h) photo, (i) captures, (j) batches floods
    SubscriberProbe probe_;
    TraceVerdict trace_verdict_;
};

int Soak::run() {
    auto fd = connect_unix_retry(o_.socket, 10000);
    if (!fd) {
        std::cerr << "gport_soak: cannot connect to " << o_.socket << "\n";
        return 2;
    }
    watcher_.fd = std::move(*fd);
    write_all(watcher_.fd.get(),
              R"({"id":0,"method":"subscribe","params":{"topics":["motion","link"]}})"
              "\n");
    probe_.start();
    for (int i = 0; i < o_.clients; ++i) {
        workers_.emplace_back(o_.socket, o_.seed * 1000 + static_cast<std::uint32_t>(i));
    }
    const auto start = now_ns();
    next_sample_ = start;
    serve(start + static_cast<std::int64_t>(o_.seconds * 1e9), true);
    // Everyone leaves; every motion they owned must still end in time.
    for (auto& w : workers_) {
        if (const auto id = w.disconnect(tally_); id != 0) {
            deadman_.on_disconnect(id, now_ns());
        }
    }
    serve(now_ns() + 1'500'000'000, false);
    attacks_.finish();
    channel_attacks_.finish();
    line_rate_attacks_.finish();
    probe_.stop();
    if (!o_.trace_path.empty()) {
        trace_verdict_ = check_burst_trace(o_.trace_path, attacks_.bursts());
    }
    deadman_.check(now_ns());
    rss_verdict_ = judge_rss(rss_, o_.rss_margin_kib, o_.rss_limit_kib);
    const bool pass = !daemon_died_ && deadman_.violations() == 0 && counters_.problems().empty() &&
                      counters_.samples() > 0 && rss_verdict_.ok && attacks_pass();
    const auto result = summary(pass);
    std::cout << result.dump(2) << "\n" << (pass ? "PASS" : "FAIL") << "\n";
    if (!o_.json_path.empty()) {
        std::ofstream(o_.json_path) << result.dump(2) << "\n";
    }
    return pass ? 0 : 1;
}

void Soak::serve(std::int64_t until_ns, bool act) {
    std::vector<pollfd> fds;
    std::vector<Worker*> owners;
    while (now_ns() < until_ns && !daemon_died_) {
        const auto t = now_ns();
        for (auto& w : workers_) {
            if (!act) {
                break;
            }
            if (const auto id = w.act(t, tally_); id != 0) {
                deadman_.on_disconnect(id, t);
            }
        }
        if (act) {
            attacks_.act(t);
            if (o_.channel_attacks) {
                channel_attacks_.act(t);
            }
            if (o_.line_rate_attacks) {
                line_rate_attacks_.act(t);
            }
        }
        fds.assign(1, pollfd{watcher_.fd.get(), POLLIN, 0});
        owners.assign(1, nullptr);
        for (auto& w : workers_) {
            if (w.connected() && !w.stalled(t)) {
                fds.push_back({w.fd(), POLLIN, 0});
                owners.push_back(&w);
            }
        }
        const auto first_attack = fds.size();
        attacks_.append_pollfds(fds);
        ::poll(fds.data(), fds.size(), 10);
        const auto t_read = now_ns();
        attacks_.on_polled(fds.data() + first_attack, fds.size() - first_attack, t_read);
        for (std::size_t i = 0; i < first_attack; ++i) {
            if (fds[i].revents == 0) {
                continue;
            }
            if (owners[i] == nullptr) {
                std::string line;
                while (read_line(watcher_.fd.get(), watcher_.pending, line, 0)) {
                    on_watcher_line(line, t_read);
                }
            } else if (!owners[i]->on_readable(tally_)) {
                ++tally_.refused;
                if (const auto id = owners[i]->disconnect(tally_); id != 0) {
                    deadman_.on_disconnect(id, t_read);
                }
            }
        }
        deadman_.check(now_ns());
        if (now_ns() >= next_sample_) {
            sample(now_ns());
        }
    }
}

void Soak::on_watcher_line(const std::string& line, std::int64_t t) {
    const auto message = json::parse(line, nullptr, false);
    if (message.is_discarded()) {
        return;
    }
    const auto method = message.value("method", "");
    if (method == "motion") {
        deadman_.on_motion(message["params"], t);
    } else if (method == "link") {
        ++watcher_.link_states[message["params"].value("state", "?")];
        attacks_.on_link(message["params"].value("state", "?"), t);
    } else if (message.contains("result") && message["result"].contains("counters")) {
        counters_.on_status(message["result"]["counters"]);
        watcher_.max_clients_seen = std::max<std::uint64_t>(
            watcher_.max_clients_seen, message["result"].value("clients", std::uint64_t{0}));
    }
}

void Soak::sample(std::int64_t t) {
    next_sample_ = t + 1'000'000'000;
    const auto p = sample_process(o_.pid);
    if (!p.alive || ::kill(o_.pid, 0) != 0) {
        daemon_died_ = true;
        return;
    }
    rss_.push_back(p.rss_kib);
    const auto request =
        R"({"id":)" + std::to_string(watcher_.next_id++) + R"(,"method":"status"})" + "\n";
    write_all(watcher_.fd.get(), request, 1000);
}

bool Soak::attacks_pass() const {
    const auto probe = probe_.figures();
    return attacks_.problems().empty() &&
           (!o_.channel_attacks || channel_attacks_.problems().empty()) &&
           line_rate_attacks_.problems().empty() && trace_verdict_.problems.empty() &&
           probe.connected && !probe.closed_by_daemon && probe.attitude_lines > 0 &&
           probe.gaps_over_limit == 0;
}

json Soak::summary(bool pass) const {
    const auto probe = probe_.figures();
    json errors = json::object();
    for (const auto& [code, count] : tally_.errors) {
        errors[std::to_string(code)] = count;
    }
    json reasons = json::object();
    for (const auto& [reason, count] : deadman_.end_reasons()) {
        reasons[reason] = count;
    }
    return {
        {"verdict", pass ? "PASS" : "FAIL"},
        {"seconds", o_.seconds},
        {"clients", o_.clients},
        {"daemon_alive_throughout", !daemon_died_},
        {"requests", tally_.requests},
        {"replies", tally_.replies},
        {"error_replies_by_code", errors},
        {"attitude_lines", tally_.attitude_lines},
        {"connects", tally_.connects},
        {"disconnects", tally_.disconnects},
        {"closed_by_daemon_or_send_failed", tally_.refused},
        {"max_clients_seen", watcher_.max_clients_seen},
        {"link_notifications", watcher_.link_states},
        {"deadman",
         {{"orphaned_speed_motions", deadman_.orphaned()},
          {"ended_after_owner_left_by_reason", reasons},
          {"worst_owner_left_to_end_ms", deadman_.max_end_ms()},
          {"violations", deadman_.violations()},
          {"notes", deadman_.violation_notes()}}},
        {"counters",
         {{"samples", counters_.samples()},
          {"problems", counters_.problems()},
          {"final", counters_.last()}}},
        {"rss_kib",
         {{"samples", rss_.size()},
          {"first_half_max", rss_verdict_.first_half_max_kib},
          {"second_half_max", rss_verdict_.second_half_max_kib},
          {"max", rss_verdict_.max_kib},
          {"margin", o_.rss_margin_kib},
          {"limit", o_.rss_limit_kib},
          {"ok", rss_verdict_.ok}}},
        {"attacks", attacks_.figures()},
        {"attack_problems", attacks_.problems()},
        {"channel_attacks", channel_attacks_.figures()},
        {"channel_attack_problems", channel_attacks_.problems()},
        {"line_rate_attacks", line_rate_attacks_.figures()},
        {"line_rate_attack_problems", line_rate_attacks_.problems()},
        {"burst_trace",
         {{"checked", trace_verdict_.checked},
          {"excused_by_vanish", trace_verdict_.excused},
          {"speeds_all_replaced_by_the_stop", trace_verdict_.unseen},
          {"problems", trace_verdict_.problems},
          {"trace", o_.trace_path}}},
        {"subscriber",
         {{"attitude_lines", probe.attitude_lines},
          {"max_gap_ms", probe.max_gap_ms},
          {"limit_ms", o_.max_gap_ms},
          {"gaps_over_limit", probe.gaps_over_limit},
          {"gaps_excused_by_link_changes", probe.excused_gaps},
          {"closed_by_daemon", probe.closed_by_daemon}}},
    };
}

}  // namespace
}  // namespace gport::bench

int main(int argc, char** argv) {
    if (argc > 1 && std::string_view(argv[1]) == "--park-child") {
        return gport::bench::park_child_main(argc - 2, argv + 2);  // the futex-waiter peer
    }
    if (argc > 1 && std::string_view(argv[1]) == "--flood-child") {
        return gport::bench::flood_child_main(argc - 2, argv + 2);  // a line-rate flood
    }
    ::signal(SIGPIPE, SIG_IGN);
    const auto options = gport::bench::parse(argc, argv);
    if (!options) {
        return 64;
    }
    gport::bench::Soak soak(*options);
    return soak.run();
}
