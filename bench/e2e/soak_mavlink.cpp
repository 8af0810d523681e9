// gport_soak_mavlink: the MAVLink-rogue attack of scripts/soak.sh (issue 22),
// against a gport-mavlink that runs with its defaults (udpin on loopback,
// vehicle 1, ground station 255) on the soak's gportd.
//
//   gport_soak_mavlink --port P --seconds S [--json OUT]
//   gport_soak_mavlink --check-trace TRACE.jsonl
//
// For S seconds, from 127.0.0.1:
//   - the vehicle (system 1, its own socket): an autopilot HEARTBEAT at 1 Hz,
//     nothing else, so that it is the reply peer; it counts the attitude
//     status it gets back;
//   - a rogue socket: 200 frames a second from system 99 (every eighth
//     claiming another random system id) with broadcast targets: an
//     autopilot HEARTBEAT, GIMBAL_DEVICE_SET_ATTITUDE to the marker angle
//     (roll 7.77, pitch -12.34, yaw 56.78), to the marker rate (11.11,
//     -22.22, 33.33 deg/s), NEUTRAL, and IMAGE_START_CAPTURE;
//   - four more sockets sending one-byte datagrams, 100 a second each.
// Exit 0 when no rogue socket got a single datagram back and the vehicle got
// attitude status. --check-trace reads gport-sim's trace (once the soak is
// over): exit 0 when no 0x85 frame carries the marker angle or rate (±0.01°).
#include <arpa/inet.h>
#include <fmt/format.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "gport/mavlink/attitude.hpp"
#include "gport/mavlink/decoder.hpp"
#include "gport/mavlink/enums.hpp"
#include "gport/mavlink/messages.hpp"
#include "posix.hpp"

namespace gm = gport::mavlink;
using gport::bench::Fd;
using gport::bench::now_ns;

namespace {

constexpr gm::Euler kMarkerAngle{7.77, -12.34, 56.78};
constexpr std::array<double, 3> kMarkerRate{11.11, -22.22, 33.33};  // degrees per second

struct Options {
    unsigned port = 0;
    double seconds = 60;
    std::string check_trace;
    std::string json;
};

// A UDP socket bound to an ephemeral port on 127.0.0.1, sending to `port`.
class Udp {
  public:
    explicit Udp(unsigned port) : fd_(::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK, 0)) {
        if (!fd_.valid()) {
            throw std::runtime_error("socket(): cannot make a UDP socket");
        }
        sockaddr_in local{};
        local.sin_family = AF_INET;
        local.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        if (::bind(fd_.get(), reinterpret_cast<sockaddr*>(&local), sizeof local) != 0) {
            throw std::runtime_error("bind(127.0.0.1:0) failed");
        }
        to_.sin_family = AF_INET;
        to_.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        to_.sin_port = htons(static_cast<std::uint16_t>(port));
    }
    void send(std::span<const std::uint8_t> bytes) {
        ::sendto(fd_.get(), bytes.data(), bytes.size(), 0, reinterpret_cast<sockaddr*>(&to_),
                 sizeof to_);
    }
    // Reads every waiting datagram; `each` gets its bytes. Returns how many.
    template <typename F>
    std::uint64_t drain(F&& each) {
        std::array<std::uint8_t, 2048> buffer{};
        std::uint64_t n = 0;
        while (true) {
            const ssize_t got = ::recv(fd_.get(), buffer.data(), buffer.size(), 0);
            if (got < 0) {
                return n;
            }
            ++n;
            each(std::span<const std::uint8_t>(buffer.data(), static_cast<std::size_t>(got)));
        }
    }
    int fd() const { return fd_.get(); }

  private:
    Fd fd_;
    sockaddr_in to_{};
};

gm::Heartbeat autopilot_heartbeat() {
    gm::Heartbeat hb;
    hb.type = 2;       // quadrotor
    hb.autopilot = 3;  // ArduPilot
    hb.system_status = gm::mav_state::kActive;
    return hb;
}

// The rogue's frame number `i`: the five kinds in turn, broadcast targets.
gm::Message rogue_message(std::uint64_t i) {
    gm::GimbalDeviceSetAttitude set;  // targets 0/0: broadcast
    constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
    switch (i % 5) {
        case 0:
            return autopilot_heartbeat();
        case 1:
            set.q = gm::to_quaternion(kMarkerAngle);
            set.angular_velocity_x = set.angular_velocity_y = set.angular_velocity_z = kNaN;
            return set;
        case 2:
            set.q = {kNaN, kNaN, kNaN, kNaN};
            set.angular_velocity_x = static_cast<float>(gm::to_radians(kMarkerRate[0]));
            set.angular_velocity_y = static_cast<float>(gm::to_radians(kMarkerRate[1]));
            set.angular_velocity_z = static_cast<float>(gm::to_radians(kMarkerRate[2]));
            return set;
        case 3:
            set.flags = gm::gimbal_flags::kNeutral;
            return set;
        default: {
            gm::CommandLong photo;
            photo.command = gm::mav_cmd::kImageStartCapture;
            return photo;
        }
    }
}

bool near_raw(const nlohmann::json& raw, const std::array<double, 3>& degrees) {
    if (!raw.is_array() || raw.size() != 3) {
        return false;
    }
    for (std::size_t i = 0; i < 3; ++i) {
        if (!raw[i].is_number() || std::abs(raw[i].get<double>() - degrees[i] * 100) > 1.5) {
            return false;
        }
    }
    return true;
}

// 0x85 frames of the trace carrying the marker angle or rate.
std::uint64_t markers_in_trace(const std::string& path) {
    std::ifstream in(path);
    std::uint64_t found = 0;
    for (std::string line; std::getline(in, line);) {
        if (line.find("0x85") == std::string::npos) {
            continue;
        }
        const auto j = nlohmann::json::parse(line, nullptr, false);
        if (j.is_discarded()) {
            continue;
        }
        if ((j.contains("angle") &&
             near_raw(j["angle"], {kMarkerAngle.roll, kMarkerAngle.pitch, kMarkerAngle.yaw})) ||
            (j.contains("speed") && near_raw(j["speed"], kMarkerRate))) {
            ++found;
        }
    }
    return found;
}

Options parse(int argc, char** argv) {
    Options o;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string key = argv[i];
        const std::string value = argv[i + 1];
        if (key == "--port") {
            o.port = static_cast<unsigned>(std::stoul(value));
        } else if (key == "--seconds") {
            o.seconds = std::stod(value);
        } else if (key == "--check-trace") {
            o.check_trace = value;
        } else if (key == "--json") {
            o.json = value;
        } else {
            throw std::invalid_argument("unknown option " + key);
        }
    }
    if (o.check_trace.empty() && (o.port == 0 || o.port > 65535 || !(o.seconds > 0))) {
        throw std::invalid_argument(
            "usage: gport_soak_mavlink --port P --seconds S [--json OUT] | --check-trace "
            "TRACE.jsonl");
    }
    return o;
}

struct Tally {
    std::uint64_t rogue_frames = 0, one_byte = 0, rogue_replies = 0;
    std::uint64_t vehicle_datagrams = 0, vehicle_status = 0;
};

Tally attack(const Options& o) {
    Udp vehicle(o.port), rogue(o.port);
    std::vector<Udp> noise;
    for (int i = 0; i < 4; ++i) {
        noise.emplace_back(o.port);
    }
    std::mt19937 rng(22);
    std::uniform_int_distribution<int> other_id(2, 254);
    gm::Decoder decoder;
    Tally t;
    const std::int64_t end = now_ns() + static_cast<std::int64_t>(o.seconds * 1e9);
    std::int64_t next_beat = 0;
    std::uint8_t seq = 0;
    for (std::int64_t tick = now_ns(); tick < end; tick = now_ns()) {
        if (tick >= next_beat) {
            vehicle.send(gm::encode(autopilot_heartbeat(), {seq++, 1, 1}).bytes());
            next_beat = tick + 1'000'000'000;
        }
        for (int k = 0; k < 2; ++k) {  // every 10 ms: 2 rogue frames, 1 byte per noise socket
            const auto sysid =
                static_cast<std::uint8_t>(t.rogue_frames % 8 == 7 ? other_id(rng) : 99);
            rogue.send(gm::encode(rogue_message(t.rogue_frames), {seq++, sysid, 1}).bytes());
            ++t.rogue_frames;
        }
        for (auto& n : noise) {
            const std::uint8_t byte = static_cast<std::uint8_t>(t.one_byte);
            n.send(std::span(&byte, 1));
            ++t.one_byte;
        }
        pollfd fds[1] = {{vehicle.fd(), POLLIN, 0}};
        ::poll(fds, 1, 10);
        t.vehicle_datagrams += vehicle.drain([&](std::span<const std::uint8_t> bytes) {
            decoder.feed(bytes, [&](const gm::FrameView& f) {
                t.vehicle_status += f.msgid == gm::GimbalDeviceAttitudeStatus::kId ? 1 : 0;
            });
        });
        auto count = [](std::span<const std::uint8_t>) {};
        t.rogue_replies += rogue.drain(count);
        for (auto& n : noise) {
            t.rogue_replies += n.drain(count);
        }
    }
    return t;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        const Options o = parse(argc, argv);
        if (!o.check_trace.empty()) {
            const std::uint64_t markers = markers_in_trace(o.check_trace);
            std::cout << fmt::format(
                "gport_soak_mavlink: rogue targets in the gimbal's trace: {}: {}\n", markers,
                markers == 0 ? "PASS" : "FAIL");
            return markers == 0 ? 0 : 1;
        }
        const Tally t = attack(o);
        const bool pass = t.rogue_replies == 0 && t.vehicle_status > 0;
        const nlohmann::json out = {{"rogue_frames", t.rogue_frames},
                                    {"one_byte_datagrams", t.one_byte},
                                    {"datagrams_to_rogues", t.rogue_replies},
                                    {"vehicle_datagrams", t.vehicle_datagrams},
                                    {"vehicle_attitude_status", t.vehicle_status},
                                    {"pass", pass}};
        if (!o.json.empty()) {
            std::ofstream(o.json) << out.dump(2) << "\n";
        }
        std::cout << fmt::format(
            "gport_soak_mavlink: {} rogue frames and {} one-byte datagrams sent; rogues got {} "
            "datagrams back; the vehicle got {} ({} attitude status): {}\n",
            t.rogue_frames, t.one_byte, t.rogue_replies, t.vehicle_datagrams, t.vehicle_status,
            pass ? "PASS" : "FAIL");
        return pass ? 0 : 1;
    } catch (const std::exception& e) {
        std::cerr << "gport_soak_mavlink: " << e.what() << "\n";
        return 64;
    }
}
