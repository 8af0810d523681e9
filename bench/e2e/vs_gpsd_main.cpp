// bench_vs_gpsd: gportd and gpsd side by side on one machine, in one run.
//
// Each daemon gets its own pseudo-terminal and the same writer (FakeGimbal):
// 0x87 frames for gportd, one $GPRMC sentence per fix for gpsd, at the same
// rate, the gpsd stream half a period after gportd's so that neither waits for
// the other's burst. W watchers of each (attitude subscribers; ?WATCH JSON
// clients) are read by one epoll loop that stamps every line the same way.
// Reported per daemon: lines, missing, latency (last byte written → line
// read) p50/p99/p99.9/max, CPU (utime+stime, % of one core), and the ratios
// gportd/gpsd. With --gportd-shm, gportd's watchers read its shared-memory
// attitude channel instead (each on its own thread, waiting on the futex;
// bench/e2e/shm_readers.hpp), timed on the same clock. Exits 1 on a wrong count (a gportd line
// missing, no gpsd line at all), a daemon that died, or gportd not exiting 0 on SIGTERM; never on a
// time; 77 (skipped) when gpsd is not installed. See docs/performance.md.
#include <arpa/inet.h>
#include <fmt/format.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string_view>
#include <thread>

#include "daemon_process.hpp"
#include "fake_gimbal.hpp"
#include "nmea.hpp"
#include "process.hpp"
#include "report.hpp"
#include "shm_readers.hpp"
#include "watchers.hpp"

#ifndef GPORT_BENCH_GPORTD
#define GPORT_BENCH_GPORTD "gportd"
#endif

namespace gport::bench {
namespace {

constexpr int kSkipped = 77;  // ctest's SKIP_RETURN_CODE

struct Options {
    int watchers = 50;
    double rate_hz = 50;
    double seconds = 5;
    std::string gportd = GPORT_BENCH_GPORTD;
    std::string gpsd = "/usr/sbin/gpsd";
    bool header = true;
    bool gportd_shm = false;  // gportd's watchers read the shared-memory channel
    int shm_threads = 0;      // threads they share; 0 = one each
};

const char* const kUsage =
    "Usage: bench_vs_gpsd [options]\n"
    "gportd and gpsd side by side: the same pty writer feeds each (0x87 frames,\n"
    "$GPRMC sentences), one epoll reader times every line of W watchers of each.\n"
    "\n"
    "  --watchers N   watchers of each daemon, 1-500 (default 50)\n"
    "  --rate HZ      frames (fixes) per second, 1-100 (default 50)\n"
    "  --seconds S    length of the measured stream, 1-600 (default 5)\n"
    "  --gportd PATH  the daemon binary (default: the one built with this bench)\n"
    "  --gpsd PATH    gpsd (default /usr/sbin/gpsd)\n"
    "  --no-header    print only the table rows\n"
    "  --gportd-shm   gportd's watchers read its shared-memory attitude channel (one\n"
    "                 thread each, waiting on the futex) instead of the socket\n"
    "  --shm-threads K  with --gportd-shm: the watchers share K threads\n";

double number(std::string_view name, const char* text, double low, double high) {
    char* end = nullptr;
    const double value = std::strtod(text, &end);
    if (end == text || *end != '\0' || value < low || value > high) {
        throw std::invalid_argument(
            fmt::format("{} must be a number from {} to {}, not '{}'", name, low, high, text));
    }
    return value;
}

Options parse(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string_view arg = argv[i];
        if (arg == "--help") {
            std::fputs(kUsage, stdout);
            std::exit(0);
        }
        if (arg == "--no-header") {
            o.header = false;
            continue;
        }
        if (arg == "--gportd-shm") {
            o.gportd_shm = true;
            continue;
        }
        if (i + 1 >= argc) {
            throw std::invalid_argument(fmt::format("unknown option or missing value: '{}'", arg));
        }
        const char* value = argv[++i];
        if (arg == "--watchers") {
            o.watchers = static_cast<int>(number(arg, value, 1, 500));
        } else if (arg == "--rate") {
            o.rate_hz = number(arg, value, 1, 100);  // NMEA time has 10 ms steps
        } else if (arg == "--seconds") {
            o.seconds = number(arg, value, 1, 600);
        } else if (arg == "--shm-threads") {
            o.shm_threads = static_cast<int>(number(arg, value, 1, 500));
        } else if (arg == "--gportd") {
            o.gportd = value;
        } else if (arg == "--gpsd") {
            o.gpsd = value;
        } else {
            throw std::invalid_argument(fmt::format("unknown option '{}' (see --help)", arg));
        }
    }
    return o;
}

// A TCP port on 127.0.0.1 that was free a moment ago, for gpsd's -S.
int free_port() {
    Fd fd(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0));
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof addr;
    if (::bind(fd.get(), reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
        ::getsockname(fd.get(), reinterpret_cast<sockaddr*>(&addr), &len) != 0) {
        throw std::runtime_error(std::string("no free TCP port: ") + std::strerror(errno));
    }
    return ntohs(addr.sin_port);
}

struct Side {
    DeliveryStats delivery;
    LatencyStats latency;
    double cpu_percent = 0;
    bool alive = false;
};

Side summarise(const std::vector<Subscriber>& watchers, const FakeGimbal& feed,
               const ProcSample& before, const ProcSample& after, double seconds) {
    Side s;
    s.delivery = delivery_of(watchers, feed.frames_written());
    s.latency = latency_of(watchers, feed.write_times());
    s.cpu_percent = 100.0 * (after.cpu_seconds - before.cpu_seconds) / seconds;
    s.alive = after.alive;
    return s;
}

std::string row(const char* name, const Options& o, const Side& s) {
    return fmt::format(
        "{:<7} {:>4} {:>5.0f} {:>8} {:>7} {:>7.0f} {:>7.0f} {:>7.0f} {:>7.0f} {:>6.2f}", name,
        o.watchers, o.rate_hz, s.delivery.delivered, s.delivery.missing, s.latency.p50_us,
        s.latency.p99_us, s.latency.p999_us, s.latency.max_us, s.cpu_percent);
}

double ratio(double a, double b) {
    return b > 0 ? a / b : 0;
}

int run(const Options& o) {
    if (::access(o.gpsd.c_str(), X_OK) != 0) {
        std::fprintf(stderr,
                     "bench_vs_gpsd: no gpsd at %s (Debian package gpsd, scripts/deps.sh); "
                     "skipped\n",
                     o.gpsd.c_str());
        return kSkipped;
    }
    raise_fd_limit();
    testing::TempDir temp("gport-vs-gpsd");  // kept when the run failed: its logs
    const std::string& base = temp.path();
    FakeGimbal gimbal;
    FakeGimbal gps;
    gps.set_payload(nmea_for);
    DaemonOptions daemon_options;
    daemon_options.binary = o.gportd;
    daemon_options.device = gimbal.device();
    daemon_options.socket = base + "/gportd.sock";
    daemon_options.config_path = base + "/gportd.jsonc";
    daemon_options.log_path = base + "/gportd.log";
    DaemonProcess gportd(daemon_options);
    const int port = free_port();
    // -N foreground, -n open the device now, -b read-only (no probing writes).
    DaemonProcess gpsd({o.gpsd, "-N", "-n", "-b", "-S", std::to_string(port), gps.device()},
                       base + "/gpsd.log");

    const auto frames = static_cast<std::size_t>(o.rate_hz * o.seconds);
    WatchHub hub;
    std::unique_ptr<ShmReaders> shm;
    if (o.gportd_shm) {
        shm =
            std::make_unique<ShmReaders>(daemon_options.socket, o.watchers, frames, o.shm_threads);
        shm->start();
    } else {
        hub.add_gportd(daemon_options.socket, o.watchers, 10000);
    }
    hub.add_gpsd(port, o.watchers, 10000);
    hub.wait_ready(10000);

    const std::string load_start = load_average();
    const auto gportd_before = sample_process(gportd.pid());
    const auto gpsd_before = sample_process(gpsd.pid());
    gimbal.start_stream(o.rate_hz, frames);
    std::this_thread::sleep_for(std::chrono::nanoseconds(static_cast<long>(0.5e9 / o.rate_hz)));
    gps.start_stream(o.rate_hz, frames);
    hub.run_for(static_cast<int>(o.seconds * 1000) + 100);
    const auto gportd_after = sample_process(gportd.pid());
    const auto gpsd_after = sample_process(gpsd.pid());
    hub.run_for(300);  // the last lines
    gimbal.stop_stream();
    gps.stop_stream();
    const std::string load_end = load_average();
    if (shm) {
        shm->stop();
    }

    const std::vector<Subscriber> shm_results =
        shm ? shm->take_results() : std::vector<Subscriber>{};
    const auto g =
        summarise(shm ? shm_results : hub.gportd(), gimbal, gportd_before, gportd_after, o.seconds);
    const auto d = summarise(hub.gpsd(), gps, gpsd_before, gpsd_after, o.seconds);
    const int gpsd_exit = gpsd.terminate();
    const int gportd_exit = gportd.terminate();

    if (o.header) {
        std::printf("load average %s -> %s; latency in µs, cpu %% of one core\n",
                    load_start.c_str(), load_end.c_str());
        std::printf(
            "daemon  watch  rate    lines missing     p50     p99   p99.9     max   cpu%%\n");
    }
    std::printf("%s\n%s\n", row(o.gportd_shm ? "gportd-shm" : "gportd", o, g).c_str(),
                row("gpsd", o, d).c_str());
    std::printf("ratio gportd%s/gpsd at %d x %.0f Hz: cpu %.2f, p50 %.2f, p99 %.2f (load %s)\n",
                o.gportd_shm ? " (shm)" : "", o.watchers, o.rate_hz,
                ratio(g.cpu_percent, d.cpu_percent), ratio(g.latency.p50_us, d.latency.p50_us),
                ratio(g.latency.p99_us, d.latency.p99_us), load_end.c_str());

    int status = 0;
    if (g.delivery.missing != 0 || g.delivery.out_of_order != 0 || !g.alive || gportd_exit != 0) {
        std::fprintf(stderr,
                     "bench_vs_gpsd: gportd: %llu lines missing, %llu out of order, exit %d\n",
                     static_cast<unsigned long long>(g.delivery.missing),
                     static_cast<unsigned long long>(g.delivery.out_of_order), gportd_exit);
        status = 1;
    }
    if (d.delivery.delivered == 0 || !d.alive) {
        std::fprintf(
            stderr,
            "bench_vs_gpsd: gpsd delivered %llu lines (alive: %d, exit %d); see %s/gpsd.log\n",
            static_cast<unsigned long long>(d.delivery.delivered), d.alive ? 1 : 0, gpsd_exit,
            base.c_str());
        status = 1;
    }
    if (status != 0) {
        temp.keep();
    }
    return status;
}

}  // namespace
}  // namespace gport::bench

int main(int argc, char** argv) {
    try {
        return gport::bench::run(gport::bench::parse(argc, argv));
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_vs_gpsd: %s\n", e.what());
        return 2;
    }
}
