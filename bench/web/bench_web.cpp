// bench_web: what browsers on gport-web cost gportd, and what they cost
// gport-web (issue 34; docs/web.md, "What browsers cost").
//
// Starts gportd on its built-in simulated gimbal and measures gportd's CPU
// over --seconds in four phases:
//   1. gportd alone;
//   2. gportd with one direct subscriber (attitude at 50 Hz over its socket),
//      the cost every comparison is made against;
//   3. gport-web with --browsers WebSocket clients on /api/live, each reading
//      everything (gportd then has one subscriber: gport-web);
//   4. as many browsers that never read: gport-web's memory must stay put.
// Prints gportd's CPU (% of one core), gport-web's CPU and RSS, and the
// messages each browser got per second.
//
//   bench_web [--browsers N] [--seconds S] [--gportd PATH] [--gport-web PATH]
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <regex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "../e2e/daemon_process.hpp"
#include "../e2e/posix.hpp"
#include "process.hpp"

namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;
using gport::bench::DaemonProcess;
using gport::bench::sample_process;

struct Options {
    int browsers = 20;
    double seconds = 10;
    std::string gportd = GPORT_BENCH_GPORTD;
    std::string gport_web = GPORT_BENCH_GPORT_WEB;
};

Options parse(int argc, char** argv) {
    Options options;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (i + 1 >= argc) {
            throw std::invalid_argument(arg +
                                        " needs a value (--browsers N, --seconds S, "
                                        "--gportd PATH, --gport-web PATH)");
        }
        const std::string value = argv[++i];
        if (arg == "--browsers") {
            options.browsers = std::stoi(value);
        } else if (arg == "--seconds") {
            options.seconds = std::stod(value);
        } else if (arg == "--gportd") {
            options.gportd = value;
        } else if (arg == "--gport-web") {
            options.gport_web = value;
        } else {
            throw std::invalid_argument("unknown option " + arg +
                                        " (allowed: --browsers, --seconds, --gportd, --gport-web)");
        }
    }
    if (options.browsers < 1 || options.browsers > 200 || options.seconds <= 0) {
        throw std::invalid_argument("--browsers must be 1 to 200 and --seconds above 0");
    }
    return options;
}

// A browser on /api/live: counts the messages it reads, or never reads.
class Browser : public std::enable_shared_from_this<Browser> {
  public:
    Browser(asio::io_context& io, bool reads) : ws_(io), reads_(reads) {}

    void open(const std::string& port, const std::string& token) {
        tcp::resolver resolver(ws_.get_executor());
        asio::connect(ws_.next_layer(), resolver.resolve("127.0.0.1", port));
        ws_.set_option(websocket::stream_base::decorator([token](websocket::request_type& req) {
            req.set(beast::http::field::authorization, "Bearer " + token);
        }));
        ws_.handshake("127.0.0.1:" + port, "/api/live");
        if (reads_) {
            read();
        }
    }
    std::uint64_t messages() const { return messages_; }
    void close() {
        beast::error_code ignored;
        ws_.next_layer().close(ignored);
    }

  private:
    void read() {
        ws_.async_read(buffer_, [self = shared_from_this()](beast::error_code error, std::size_t) {
            if (error) {
                return;
            }
            ++self->messages_;
            self->buffer_.consume(self->buffer_.size());
            self->read();
        });
    }

    websocket::stream<tcp::socket, false> ws_;  // as gport-web: no deflate
    beast::flat_buffer buffer_;
    bool reads_;
    std::uint64_t messages_ = 0;
};

// The port gport-web printed ("gport-web: serving http://127.0.0.1:PORT/").
std::string served_port(const std::string& log) {
    const std::regex served(R"(serving https?://127\.0\.0\.1:([0-9]+)/)");
    for (int i = 0; i < 100; ++i) {
        std::ifstream in(log);
        std::string line;
        std::smatch match;
        while (std::getline(in, line)) {
            if (std::regex_search(line, match, served)) {
                return match[1];
            }
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    throw std::runtime_error("gport-web did not say where it serves (log " + log + ")");
}

struct Cost {
    double gportd_cpu = 0;  // % of one core
    double web_cpu = 0;
    long web_rss_kib = 0;
};

// CPU of gportd (and gport-web, when given) over `seconds`, as % of a core.
Cost measure(pid_t gportd, pid_t web, double seconds) {
    const auto d0 = sample_process(gportd);
    const auto w0 = web > 0 ? sample_process(web) : gport::bench::ProcSample{};
    std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
    const auto d1 = sample_process(gportd);
    Cost cost;
    cost.gportd_cpu = 100 * (d1.cpu_seconds - d0.cpu_seconds) / seconds;
    if (web > 0) {
        const auto w1 = sample_process(web);
        cost.web_cpu = 100 * (w1.cpu_seconds - w0.cpu_seconds) / seconds;
        cost.web_rss_kib = w1.rss_kib;
    }
    return cost;
}

// One subscriber straight on gportd's socket, reading everything.
std::thread direct_subscriber(const std::string& socket, const std::atomic<bool>& stop) {
    auto fd = gport::bench::connect_unix_retry(socket, 5000);
    if (!fd) {
        throw std::runtime_error("gportd's socket " + socket + " does not answer");
    }
    const std::string subscribe =
        R"({"jsonrpc":"2.0","id":1,"method":"subscribe","params":{"topics":["attitude"],)"
        R"("max_rate_hz":50}})"
        "\n";
    gport::bench::write_all(fd->get(), subscribe);
    return std::thread([fd = std::move(*fd), &stop]() mutable {
        std::string pending;
        std::string line;
        while (!stop) {
            gport::bench::read_line(fd.get(), pending, line, 200);
        }
    });
}

void run_in(const Options& options, const std::string& dir) {
    const std::string socket = dir + "/gportd.sock";
    const std::string token = "benchbenchbenchbenchbenchbench01";
    {
        std::ofstream(dir + "/gportd.json") << "{}\n";
        std::ofstream(dir + "/token") << "control:" << token << "\n";
        chmod((dir + "/token").c_str(), 0600);
    }
    DaemonProcess gportd({options.gportd, "--simulate", "--config", dir + "/gportd.json",
                          "--socket", socket, "--state-dir", dir, "--log-level", "warn"},
                         dir + "/gportd.log");
    if (!gport::bench::connect_unix_retry(socket, 10000)) {
        throw std::runtime_error("gportd did not start (log " + dir + "/gportd.log)");
    }
    const double s = options.seconds;
    std::printf("bench_web: %d browsers, %.1f s per phase, load %s\n", options.browsers, s,
                gport::bench::load_average().c_str());

    const Cost alone = measure(gportd.pid(), -1, s);
    std::atomic<bool> stop = false;
    auto subscriber = direct_subscriber(socket, stop);
    const Cost one = measure(gportd.pid(), -1, s);
    stop = true;
    subscriber.join();

    DaemonProcess web({options.gport_web, "--socket", socket, "--listen", "127.0.0.1:0",
                       "--token-file", dir + "/token"},
                      dir + "/gport-web.log");
    const std::string port = served_port(dir + "/gport-web.log");
    asio::io_context io;
    std::vector<std::shared_ptr<Browser>> browsers;
    for (int i = 0; i < options.browsers; ++i) {
        browsers.push_back(std::make_shared<Browser>(io, true));
        browsers.back()->open(port, token);
    }
    std::thread loop([&io] { io.run(); });
    std::this_thread::sleep_for(std::chrono::seconds(1));
    std::uint64_t before = 0;
    for (const auto& b : browsers) {
        before += b->messages();
    }
    const Cost reading = measure(gportd.pid(), web.pid(), s);
    std::uint64_t after = 0;
    for (const auto& b : browsers) {
        after += b->messages();
    }
    for (const auto& b : browsers) {
        b->close();
    }
    io.stop();
    loop.join();

    asio::io_context idle_io;
    std::vector<std::shared_ptr<Browser>> stalled;
    for (int i = 0; i < options.browsers; ++i) {
        stalled.push_back(std::make_shared<Browser>(idle_io, false));
        stalled.back()->open(port, token);
    }
    const long rss_start = sample_process(web.pid()).rss_kib;
    const Cost stalling = measure(gportd.pid(), web.pid(), s);
    const auto web_end = sample_process(web.pid());

    std::printf("%-44s %10s %10s %12s\n", "phase", "gportd %", "web %", "web RSS KiB");
    std::printf("%-44s %10.2f %10s %12s\n", "gportd alone", alone.gportd_cpu, "-", "-");
    std::printf("%-44s %10.2f %10s %12s\n", "+ 1 direct subscriber (attitude 50 Hz)",
                one.gportd_cpu, "-", "-");
    std::printf("%-44s %10.2f %10.2f %12ld\n",
                ("+ gport-web, " + std::to_string(options.browsers) + " browsers reading").c_str(),
                reading.gportd_cpu, reading.web_cpu, reading.web_rss_kib);
    std::printf(
        "%-44s %10.2f %10.2f %12ld\n",
        ("+ gport-web, " + std::to_string(options.browsers) + " browsers never reading").c_str(),
        stalling.gportd_cpu, stalling.web_cpu, web_end.rss_kib);
    std::printf("messages per browser per second: %.1f\n",
                static_cast<double>(after - before) / options.browsers / s);
    std::printf(
        "gport-web RSS while browsers never read: %ld KiB at the start, %ld KiB after "
        "%.1f s (peak %ld KiB)\n",
        rss_start, web_end.rss_kib, s, web_end.hwm_kib);
    std::printf(
        "gportd's extra CPU for gport-web and its browsers: %+.2f %% of a core; for one "
        "direct subscriber: %+.2f %%\n",
        reading.gportd_cpu - alone.gportd_cpu, one.gportd_cpu - alone.gportd_cpu);
    for (const auto& b : stalled) {
        b->close();
    }
    web.terminate();
    gportd.terminate();
}

// In a fresh directory, removed after the run and kept after an error: the
// logs it names are there.
void run(const Options& options) {
    gport::testing::TempDir temp("bench_web");
    try {
        run_in(options, temp.path());
    } catch (...) {
        temp.keep();
        throw;
    }
}

}  // namespace

int main(int argc, char** argv) {
    try {
        run(parse(argc, argv));
    } catch (const std::exception& e) {
        std::cerr << "bench_web: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
