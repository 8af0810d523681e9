#include "rig.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <regex>
#include <stdexcept>
#include <thread>

#include "../e2e/posix.hpp"
#include "gport/mavlink/enums.hpp"
#include "mavlink_link.hpp"

namespace gport::bench::relay {
namespace {

constexpr unsigned kBaud = 115200;
constexpr double kAttitudeHz = 50;
constexpr int kSeedCaptures = 200;
constexpr std::int64_t kReadyTimeoutNs = 10'000'000'000;

// Photos in gportd's capture log, written before it starts (its line
// format, docs/operations.md "The capture log"), each with a position meta
// as gport-mavlink gives: what /api/captures.csv pages through.
void seed_captures(const std::string& dir, int count) {
    std::ofstream out(dir + "/captures.jsonl");
    const auto mono_us = now_ns() / 1000;
    for (int i = 1; i <= count; ++i) {
        out << R"({"index":)" << i << R"(,"kind":"photo","utc_us":)"
            << 1'700'000'000'000'000LL + i * 1'000'000LL << R"(,"mono_us":)" << mono_us - count + i
            << R"(,"attitude":null,"client":{"pid":1,"uid":0,"name":"bench_relay_stop"},)"
            << R"("meta":{"lat":47.3977)" << i << R"(,"lon":8.5456)" << i
            << R"(,"alt_m":488.5,"relative_alt_m":30.25}})"
            << "\n";
    }
    if (!out) {
        throw std::runtime_error("cannot seed the capture log in " + dir);
    }
}

// Waits until gportd says its line is open.
void wait_line_open(const std::string& socket) {
    auto fd = connect_unix_retry(socket, 10'000);
    const auto deadline = now_ns() + kReadyTimeoutNs;
    std::string pending;
    std::string line;
    while (fd && now_ns() < deadline) {
        write_all(fd->get(), "{\"id\":1,\"method\":\"status\"}\n");
        if (read_line(fd->get(), pending, line, 5000) &&
            line.find(R"("device_open":true)") != std::string::npos) {
            return;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    throw std::runtime_error("gportd did not open the line within 10 s");
}

int count_lines(const std::string& path, const std::string& text) {
    std::ifstream in(path);
    int n = 0;
    for (std::string line; std::getline(in, line);) {
        n += line.find(text) != std::string::npos ? 1 : 0;
    }
    return n;
}

// The port of gport-web's "gport-web: serving http://127.0.0.1:PORT/" line.
unsigned short served_port(const std::string& log, DaemonProcess& web) {
    const std::regex served(R"(serving http://127\.0\.0\.1:([0-9]+)/)");
    for (int i = 0; i < 100 && web.running(); ++i) {
        std::ifstream in(log);
        std::smatch match;
        for (std::string line; std::getline(in, line);) {
            if (std::regex_search(line, match, served)) {
                return static_cast<unsigned short>(std::stoi(match[1]));
            }
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    throw std::runtime_error("gport-web did not say where it serves (log " + log + ")");
}

bool gimbal_active(const gm::Message& message, std::uint8_t compid) {
    const auto* heartbeat = std::get_if<gm::Heartbeat>(&message);
    return heartbeat && compid == gm::mav_comp_id::kGimbal &&
           heartbeat->system_status == gm::mav_state::kActive;
}

// Heartbeats as the vehicle until the gimbal's heartbeat says ACTIVE
// (gportd reached and its link up).
bool wait_mavlink_active(unsigned port, DaemonProcess& bridge) {
    MavlinkPeer vehicle(port, kVehicle, gm::mav_comp_id::kAutopilot1);
    const auto deadline = now_ns() + kReadyTimeoutNs;
    bool active = false;
    while (!active && now_ns() < deadline && bridge.running()) {
        vehicle.send(autopilot_heartbeat());
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
        vehicle.drain([&](const gm::Message& m, std::uint8_t c) { active |= gimbal_active(m, c); });
    }
    return active;
}

}  // namespace

Rig::Rig(const Options& options) {
    start_gportd(options);
    start_web(options);
    start_mavlink(options);
}

Rig::~Rig() {
    finish();
}

void Rig::start_gportd(const Options& options) {
    const std::string& dir = dir_.path();
    ::mkdir((dir + "/state").c_str(), 0755);
    seed_captures(dir + "/state", kSeedCaptures);
    sim_ = std::make_unique<LineSim>(kBaud, kAttitudeHz, dir + "/gimbal");
    DaemonOptions d;
    d.binary = options.gportd;
    d.device = sim_->device();
    d.socket = dir + "/gportd.sock";
    d.config_path = dir + "/gportd.json";
    d.log_path = dir + "/gportd.log";
    d.max_clients = 100;
    d.max_duration_ms = 60000;  // gportd's default
    d.log_level = "info";
    d.max_requests_per_s = 0;  // gportd's own per-client limit, as shipped (200/s)
    d.extra_args = {"--state-dir", dir + "/state"};
    gportd_ = std::make_unique<DaemonProcess>(d);
    wait_line_open(d.socket);
    watch_ = std::make_unique<MotionWatch>(d.socket);
}

void Rig::start_web(const Options& options) {
    const std::string& dir = dir_.path();
    web_target_.control_token = "relay-bench-control-0123456789";
    web_target_.view_token = "relay-bench-view-0123456789";
    const std::string token_file = dir + "/token";
    std::ofstream(token_file) << "control:" << web_target_.control_token << "\n"
                              << "view:" << web_target_.view_token << "\n";
    ::chmod(token_file.c_str(), 0600);
    web_ = std::make_unique<DaemonProcess>(
        std::vector<std::string>{options.gport_web, "--socket", dir + "/gportd.sock", "--listen",
                                 "127.0.0.1:0", "--token-file", token_file},
        dir + "/gport-web.log");
    web_target_.port = served_port(dir + "/gport-web.log", *web_);
    HttpConnection http(web_target_, web_target_.view_token);
    const auto deadline = now_ns() + kReadyTimeoutNs;
    while (http.request(http::verb::get, "/api/status") != 200u) {
        if (now_ns() > deadline || !web_->running()) {
            throw std::runtime_error("gport-web never answered /api/status (log " + dir +
                                     "/gport-web.log)");
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
}

void Rig::start_mavlink(const Options& options) {
    const std::string& dir = dir_.path();
    for (int attempt = 0; attempt < 3 && !mavlink_port_; ++attempt) {
        const unsigned port = free_udp_port();
        mavlink_ = std::make_unique<DaemonProcess>(
            std::vector<std::string>{options.gport_mavlink, "--socket", dir + "/gportd.sock",
                                     "--mavlink", "udpin:127.0.0.1:" + std::to_string(port),
                                     "--sysid", "1", "--gcs-sysid", "255"},
            dir + "/gport-mavlink.log");
        if (wait_mavlink_active(port, *mavlink_)) {
            mavlink_port_ = port;
        } else if (mavlink_->running()) {
            break;  // it runs but never became active: not a port taken by another
        }
    }
    if (!mavlink_port_) {
        throw std::runtime_error("gport-mavlink never reported an active gimbal (log " + dir +
                                 "/gport-mavlink.log)");
    }
}

Marks Rig::marks() const {
    Marks m;
    m.web_drops = count_lines(dir_.path() + "/gport-web.log", "gportd not reachable");
    m.mavlink_drops = count_lines(dir_.path() + "/gport-mavlink.log", "connection lost");
    m.lease_endings = watch_ ? watch_->lease_endings() : 0;
    return m;
}

Exits Rig::finish() {
    Exits exits;
    if (mavlink_) {
        exits.gport_mavlink = mavlink_->terminate();
    }
    if (web_) {
        exits.gport_web = web_->terminate();
    }
    watch_.reset();
    if (gportd_) {
        exits.gportd = gportd_->terminate();
    }
    return exits;
}

}  // namespace gport::bench::relay
