// bench_e2e: end-to-end load generator for gportd. It plays the gimbal on a
// pseudo-terminal, starts the real daemon on it, connects subscribers (and
// optionally clients that flood the socket with requests), and measures
// latency from the last byte of each 0x87 frame to each subscriber's JSON
// line, the daemon's CPU and memory, delivery, and keepalive timing.
// See docs/performance.md.
#include <stdlib.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>

#include "clients.hpp"
#include "daemon_process.hpp"
#include "fake_gimbal.hpp"
#include "line_flood.hpp"
#include "line_rate.hpp"
#include "options.hpp"
#include "park_attack.hpp"
#include "posix.hpp"
#include "process.hpp"
#include "report.hpp"
#include "shm_readers.hpp"
#include "socket_readers.hpp"
#include "stop_pinger.hpp"
#include "stop_probe.hpp"

namespace gport::bench {
namespace {

using nlohmann::json;

// One request on the control connection; returns the parsed reply.
json request(Fd& fd, std::string& pending, const json& message) {
    if (!write_all(fd.get(), message.dump() + "\n")) {
        throw std::runtime_error("control connection: cannot send " + message.dump());
    }
    std::string line;
    if (!read_line(fd.get(), pending, line, 10000)) {
        throw std::runtime_error("control connection: no reply to " + message.dump());
    }
    return json::parse(line);
}

void wait_device_open(Fd& control, std::string& pending) {
    const auto deadline = now_ns() + 10'000'000'000LL;
    while (now_ns() < deadline) {
        const auto reply = request(control, pending, {{"id", 1}, {"method", "status"}});
        if (reply.at("result").value("device_open", false)) {
            return;
        }
        ::usleep(20'000);
    }
    throw std::runtime_error("gportd did not open the pty within 10 s");
}

std::string tail_of(const std::string& path) {
    std::ifstream in(path);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return text.size() > 2000 ? text.substr(text.size() - 2000) : text;
}

// What the futex-waiter attack and the stop pinger saw (issue 22).
struct AttackResult {
    int park_threads = 0;
    bool park_gone = false;
    int park_keys = 0;
    int channel_version = 0;
    PingStats pings;
    std::string ping_error;
};

// Lines still on their way: a loaded machine delays them, it does not lose
// them. Serves the subscribers until every reader has the last frame
// written, for at least 300 ms and at most 5 s; what is still missing then
// is counted as missing.
void drain(ClientHub& hub, const ShmReaders* shm, const SocketReaders* threaded,
           std::uint32_t last) {
    const auto deadline = now_ns() + 5'000'000'000LL;
    hub.run_for(300);
    while (now_ns() < deadline &&
           !(hub.caught_up(last) && (shm == nullptr || shm->caught_up(last)) &&
             (threaded == nullptr || threaded->caught_up(last)))) {
        hub.run_for(50);
    }
}

CellResult run_cell(const Options& options, const std::string& dir, AttackResult& attack) {
    CellResult r;
    r.rate_hz = options.rate_hz;
    r.subscribers = options.subscribers;
    r.shm_readers = options.shm_readers;
    r.flooders = options.flooders;
    r.seconds = options.seconds;

    FakeGimbal gimbal;
    DaemonOptions daemon_options;
    daemon_options.binary = options.gportd;
    daemon_options.device = gimbal.device();
    daemon_options.socket = dir + "/gportd.sock";
    daemon_options.config_path = dir + "/gportd.json";
    daemon_options.log_path = dir + "/gportd.log";
    daemon_options.max_clients = options.subscribers + options.shm_readers + options.flooders + 20;
    daemon_options.realtime = options.daemon_fifo;
    daemon_options.realtime_priority = options.realtime_priority;
    DaemonProcess daemon(daemon_options);

    auto control = connect_unix_retry(daemon_options.socket, 10000);
    if (!control) {
        throw std::runtime_error("gportd never listened on " + daemon_options.socket +
                                 "; its log:\n" + tail_of(daemon_options.log_path));
    }
    std::string pending;
    wait_device_open(*control, pending);

    const auto frames = static_cast<std::size_t>(options.rate_hz * options.seconds);
    ClientHub hub;
    std::unique_ptr<SocketReaders> threaded;
    if (options.subscriber_threads) {
        threaded =
            std::make_unique<SocketReaders>(daemon_options.socket, options.subscribers, frames);
    } else {
        hub.add_subscribers(daemon_options.socket, options.subscribers, 60000);
    }
    hub.add_flooders(daemon_options.socket, options.flooders);
    std::unique_ptr<ShmReaders> shm;
    if (options.shm_readers > 0) {
        shm = std::make_unique<ShmReaders>(daemon_options.socket, options.shm_readers, frames,
                                           options.shm_threads);
        shm->start();
    }

    // One speed command that outlasts the run: its 10 Hz keepalive is timed.
    const int duration_ms = static_cast<int>(options.seconds * 1000) + 10000;
    request(
        *control, pending,
        {{"id", 2}, {"method", "speed"}, {"params", {{"yaw", 5.0}, {"duration_ms", duration_ms}}}});

    std::unique_ptr<ParkAttack> park;
    if (options.park_threads > 0) {
        park = std::make_unique<ParkAttack>(daemon_options.socket, options.park_threads,
                                            options.park_gone, options.park_keys);
        attack.channel_version = park->version();
    }
    StopPinger pinger(daemon_options.socket, std::max(options.stop_every_ms, 1));
    StopProbe probe(daemon_options.socket, gimbal, options.stops, options.seconds);
    r.load_start = load_average();
    const auto before = sample_process(daemon.pid());
    const auto t0 = now_ns();
    gimbal.start_stream(options.rate_hz, frames);
    hub.start_flood();
    if (options.stops > 0) {
        probe.start();
    }
    if (options.stop_every_ms > 0) {
        pinger.start();
    }
    hub.run_for(static_cast<int>(options.seconds * 1000) + 20);
    const auto t1 = now_ns();
    probe.join();
    const auto after = sample_process(daemon.pid());
    pinger.stop();
    if (park) {
        park->stop();
    }
    attack.park_threads = options.park_threads;
    attack.park_gone = options.park_gone;
    attack.park_keys = options.park_keys;
    attack.pings = pinger.stats();
    attack.ping_error = pinger.error();
    hub.stop_flood();
    gimbal.stop_stream();
    drain(hub, shm.get(), threaded.get(), gimbal.frames_written());
    if (shm) {
        shm->stop();
        hub.adopt(shm->take_results());
    }
    if (threaded) {
        threaded->stop();
        hub.adopt(threaded->take_results());
    }

    const auto status = request(*control, pending, {{"id", 3}, {"method", "status"}});
    r.daemon_counters = status.at("result").at("counters");
    request(*control, pending, {{"id", 4}, {"method", "stop"}});
    r.load_end = load_average();
    r.daemon_exit = daemon.terminate();
    gimbal.stop_reader();

    const double wall = static_cast<double>(t1 - t0) / 1e9;
    r.cpu_percent = 100.0 * (after.cpu_seconds - before.cpu_seconds) / wall;
    r.system_percent = 100.0 * (after.system_seconds - before.system_seconds) / wall;
    r.rss_kib = after.rss_kib;
    r.hwm_kib = after.hwm_kib;
    r.frames_written = gimbal.frames_written();
    r.writer_late = gimbal.late_frames();
    r.realtime = gimbal.realtime();
    r.daemon_fifo = options.daemon_fifo;
    r.realtime_priority = options.realtime_priority;
    r.delivery = delivery_of(hub.subscribers(), r.frames_written);
    r.latency = latency_of(hub.subscribers(), gimbal.write_times());
    r.keepalive = keepalive_of(gimbal.control_frames(), t0, t1, 1000.0 / options.keepalive_hz,
                               probe.motion_starts());
    r.stops = stops_of(probe.samples(), gimbal.control_frames());
    r.stops.per_cause = options.stops;
    r.stops.error = probe.error();
    r.flood_replies_per_s = static_cast<double>(hub.flood_replies()) / wall;
    return r;
}

int run(const Options& options) {
    raise_fd_limit();
    const testing::TempDir dir("gport-bench");
    AttackResult attack;
    const auto result = run_cell(options, dir.path(), attack);
    if (!options.no_header) {
        std::cout << table_header();
    }
    std::cout << table_row(result) << stop_table(result.stops);
    if (attack.park_threads > 0) {
        std::cout << "  futex-waiter attack: " << attack.park_threads
                  << " threads parked by a read-only peer"
                  << (attack.park_gone ? " that disconnected (+ 1 real holder)" : "")
                  << (attack.park_keys > 0
                          ? " on " + std::to_string(attack.park_keys) + " keys of its own"
                          : std::string(" on its wake word"))
                  << ", channel version " << attack.channel_version << "\n";
    }
    if (options.stop_every_ms > 0) {
        std::cout << ping_line(attack.pings, options.stop_every_ms);
    }
    std::cout << std::flush;
    if (!options.json_path.empty()) {
        auto summary = to_json(result);
        summary["park"] = {{"threads", attack.park_threads},
                           {"gone", attack.park_gone},
                           {"keys", attack.park_keys},
                           {"channel_version", attack.channel_version}};
        summary["stop_round_trip"] = to_json(attack.pings);
        std::ofstream out(options.json_path);
        out << summary.dump(2) << "\n";
    }
    // Never a time: only a crash or a wrong count fails the run (the short CI form).
    const auto& d = result.delivery;
    if (d.missing > d.reported_dropped || d.out_of_order != 0) {
        std::cerr << "bench_e2e: " << d.missing << " lines missing but " << d.reported_dropped
                  << " reported dropped, " << d.out_of_order << " out of order\n";
        return 1;
    }
    // A stop that never reached the pty fails the run; a slow one does not.
    const auto& s = result.stops;
    if (!s.error.empty() || s.request.lost + s.disconnect.lost != 0) {
        std::cerr << "bench_e2e: stop probe: " << s.request.lost << " `stop` and "
                  << s.disconnect.lost << " disconnect stops never reached the pty"
                  << (s.error.empty() ? "" : "; " + s.error) << "\n";
        return 1;
    }
    if (!attack.ping_error.empty()) {
        std::cerr << "bench_e2e: " << attack.ping_error << "\n";
        return 1;
    }
    return result.daemon_exit == 0 ? 0 : 1;
}

}  // namespace
}  // namespace gport::bench

int main(int argc, char** argv) {
    if (argc > 1 && std::string_view(argv[1]) == "--park-child") {
        return gport::bench::park_child_main(argc - 2, argv + 2);  // the attack's peer
    }
    if (argc > 1 && std::string_view(argv[1]) == "--flood-child") {
        return gport::bench::flood_child_main(argc - 2, argv + 2);  // a line-rate flood
    }
    const auto options = gport::bench::parse_options(argc, argv);
    if (!options) {
        return 64;  // EX_USAGE; parse_options printed why
    }
    if (options->help) {
        std::cout << gport::bench::usage();
        return 0;
    }
    try {
        if (!options->line_rate.empty()) {
            return gport::bench::run_line_rate(*options);
        }
        return gport::bench::run(*options);
    } catch (const std::exception& error) {
        std::cerr << "bench_e2e: " << error.what() << "\n";
        return 1;
    }
}
