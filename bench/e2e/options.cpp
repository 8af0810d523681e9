#include "options.hpp"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "stop_probe.hpp"

#ifndef GPORT_BENCH_GPORTD
#define GPORT_BENCH_GPORTD "gportd"
#endif

namespace gport::bench {
namespace {

// A number in [low, high], or nullopt with a message naming the option.
std::optional<double> number(std::string_view name, const char* text, double low, double high) {
    char* end = nullptr;
    const double value = std::strtod(text, &end);
    if (end == text || *end != '\0' || value < low || value > high) {
        std::fprintf(stderr, "bench_e2e: %.*s must be a number from %g to %g, not '%s'\n",
                     static_cast<int>(name.size()), name.data(), low, high, text);
        return std::nullopt;
    }
    return value;
}

}  // namespace

std::string usage() {
    return "Usage: bench_e2e [options]\n"
           "End-to-end load test of gportd: plays the gimbal on a pty, starts gportd on it,\n"
           "and measures latency, CPU, memory, delivery and keepalive timing.\n"
           "\n"
           "  --rate HZ          0x87 frames per second, 1-20000 (default 200)\n"
           "  --subscribers N    attitude subscribers, 0-4000 (default 100)\n"
           "  --shm N            readers of the shared-memory attitude channel, 0-4000, each on\n"
           "                     its own thread waiting on the futex (default 0; without\n"
           "                     --subscribers, --shm makes the socket subscribers 0; with\n"
           "                     --line-rate, they read through every scenario)\n"
           "  --shm-threads K    the --shm readers share K threads (default: one each)\n"
           "  --subscriber-threads  each socket subscriber reads on its own thread, blocking\n"
           "                     in read() as separate processes would (default: one epoll loop)\n"
           "  --flood N          clients sending status requests back to back, 0-100 (default 0)\n"
           "  --seconds S        length of the measured stream, 1-600 (default 5)\n"
           "  --gportd PATH      the daemon binary (default: the one built with this bench)\n"
           "  --json FILE        also write the results as JSON to FILE\n"
           "  --no-header        print only the table row\n"
           "  --realtime N       gportd's config sets realtime.priority N and lock_memory\n"
           "                     (the product's option; a warning in its log when refused)\n"
           "  --daemon-fifo      run gportd SCHED_FIFO (needs root or CAP_SYS_NICE): shows how\n"
           "                     much of a delay is waiting for a CPU on a loaded machine\n"
           "  --stops N          N motions ended by `stop` and N by closing the owner's\n"
           "                     connection, spread over the run; reports the delay from each\n"
           "                     cause to the zero speed on the pty (count, lost, p50, p99,\n"
           "                     max per cause); a stop that never reaches the pty fails the\n"
           "                     run, a slow one never does. 0-1000, at most 12.5 per\n"
           "                     second of --seconds\n"
           "  --park-threads N   the futex-waiter attack (issue 22): a read-only peer, a process\n"
           "                     of its own, opens the attitude channel and parks N threads\n"
           "                     (0-20000) on the word gportd wakes (version 1: the ring's;\n"
           "                     version 2: its connection's wake block); implies\n"
           "                     --stop-every 20 unless given\n"
           "  --park-gone        the parking peer closes its socket once parked, keeping its\n"
           "                     threads; another connection keeps the channel open\n"
           "  --park-keys K      the parked threads wait, round robin, on K words (1-65536) of\n"
           "                     a shared memfd of the peer's own instead of the wake word:\n"
           "                     with K in the thousands every futex hash bucket, the wake\n"
           "                     word's too, holds waiters gportd's wake walks past\n"
           "  --stop-every MS    a commander sends `stop` every MS ms (1-1000) and the stop\n"
           "                     round trip (write to reply) is reported: count, p50, p99, max\n"
           "  --line-rate LIST   instead: the stop on the wire with the gimbal draining the line\n"
           "                     at 115200 baud (gport-sim's simulator, --baud), for each\n"
           "                     scenario in LIST (idle,photo,captures,batches,every,vehicle\n"
           "                     or all; every: 16 read-only peers cycling through every\n"
           "                     method; vehicle: the trusted source sending publish_vehicle\n"
           "                     back to back, a photo every 50th): stop\n"
           "                     p50/p99/max from `stop` written to the zero speed's last byte\n"
           "                     read, the longest attitude gap a subscriber saw, and whether\n"
           "                     gportd logged `link stale` (--stops N stops each, default 20)\n"
           "  --reader-uid UID   the read-only floods run as UID (default 65534 when root;\n"
           "                     otherwise our own uid, which may command)\n"
           "  --keep-logs        keep each line-rate run's directory and gportd log\n"
           "  --camera-rate N    line rate: gportd's camera.max_commands_per_s (0.1 to 1000;\n"
           "                     default: as shipped, 5), e.g. 1000 to flood the line itself\n"
           "  -h, --help         this text\n";
}

std::optional<Options> parse_options(int argc, char** argv) {
    Options o;
    o.gportd = GPORT_BENCH_GPORTD;
    bool subscribers_given = false;
    bool stop_every_given = false;
    bool reader_given = false;
    for (int i = 1; i < argc; ++i) {
        const std::string_view arg = argv[i];
        if (arg == "-h" || arg == "--help") {
            o.help = true;
            continue;
        }
        if (arg == "--no-header") {
            o.no_header = true;
            continue;
        }
        if (arg == "--subscriber-threads") {
            o.subscriber_threads = true;
            continue;
        }
        if (arg == "--daemon-fifo") {
            o.daemon_fifo = true;
            continue;
        }
        if (arg == "--park-gone") {
            o.park_gone = true;
            continue;
        }
        if (arg == "--keep-logs") {
            o.keep_logs = true;
            continue;
        }
        if (i + 1 >= argc) {
            std::fprintf(stderr, "bench_e2e: unknown option or missing value: %s\n%s", argv[i],
                         usage().c_str());
            return std::nullopt;
        }
        const char* value = argv[++i];
        std::optional<double> n = 0.0;
        if (arg == "--rate") {
            n = number(arg, value, 1, 20000);
            o.rate_hz = n.value_or(0);
        } else if (arg == "--subscribers") {
            n = number(arg, value, 0, 4000);
            o.subscribers = static_cast<int>(n.value_or(0));
            subscribers_given = true;
        } else if (arg == "--shm-threads") {
            n = number(arg, value, 1, 4000);
            o.shm_threads = static_cast<int>(n.value_or(0));
        } else if (arg == "--shm") {
            n = number(arg, value, 0, 4000);
            o.shm_readers = static_cast<int>(n.value_or(0));
        } else if (arg == "--camera-rate") {
            n = number(arg, value, 0.1, 1000);
            o.camera_rate = n.value_or(0);
        } else if (arg == "--realtime") {
            n = number(arg, value, 1, 99);
            o.realtime_priority = static_cast<int>(n.value_or(0));
        } else if (arg == "--flood") {
            n = number(arg, value, 0, 100);
            o.flooders = static_cast<int>(n.value_or(0));
        } else if (arg == "--seconds") {
            n = number(arg, value, 1, 600);
            o.seconds = n.value_or(0);
        } else if (arg == "--stops") {
            n = number(arg, value, 0, 1000);
            o.stops = static_cast<int>(n.value_or(0));
        } else if (arg == "--park-threads") {
            n = number(arg, value, 0, 20000);
            o.park_threads = static_cast<int>(n.value_or(0));
        } else if (arg == "--park-keys") {
            n = number(arg, value, 1, 65536);
            o.park_keys = static_cast<int>(n.value_or(0));
        } else if (arg == "--stop-every") {
            n = number(arg, value, 1, 1000);
            o.stop_every_ms = static_cast<int>(n.value_or(0));
            stop_every_given = true;
        } else if (arg == "--line-rate") {
            o.line_rate = value;
        } else if (arg == "--reader-uid") {
            n = number(arg, value, 0, 4294967294.0);
            o.reader_uid = static_cast<unsigned>(n.value_or(0));
            reader_given = true;
        } else if (arg == "--gportd") {
            o.gportd = value;
        } else if (arg == "--json") {
            o.json_path = value;
        } else {
            std::fprintf(stderr, "bench_e2e: unknown option %s\n%s", argv[i - 1], usage().c_str());
            return std::nullopt;
        }
        if (!n) {
            return std::nullopt;
        }
    }
    // Each motion's cycle needs kMinStopCycleMs (start, move, stop, settle).
    if (o.line_rate.empty() && 2.0 * o.stops * kMinStopCycleMs > o.seconds * 1000) {
        std::fprintf(stderr,
                     "bench_e2e: --stops %d needs %g s at least (%g ms per motion, two causes); "
                     "raise --seconds or lower --stops\n",
                     o.stops, 2.0 * o.stops * kMinStopCycleMs / 1000, kMinStopCycleMs);
        return std::nullopt;
    }
    if (o.shm_readers > 0 && !subscribers_given) {
        o.subscribers = 0;
    }
    if (o.park_gone && o.park_threads == 0) {
        std::fprintf(stderr, "bench_e2e: --park-gone needs --park-threads N\n");
        return std::nullopt;
    }
    if (o.park_keys > 0 && o.park_threads == 0) {
        std::fprintf(stderr, "bench_e2e: --park-keys needs --park-threads N\n");
        return std::nullopt;
    }
    if (!reader_given && ::geteuid() == 0) {
        o.reader_uid = 65534;
    }
    if (o.park_threads > 0 && !stop_every_given) {
        o.stop_every_ms = 20;
    }
    return o;
}

}  // namespace gport::bench
