#include "line_flood.hpp"

#include <fcntl.h>
#include <grp.h>
#include <poll.h>
#include <unistd.h>

#include <array>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "posix.hpp"

extern char** environ;

namespace gport::bench {
namespace {

constexpr int kBatch = 32;

std::string one(const char* method, const std::string& params = "{}") {
    return std::string(R"({"id":1,"method":")") + method + R"(","params":)" + params + "}";
}

// What one connection sends per round and how many replies that asks for.
struct Round {
    std::string text;
    int replies = 1;
};

Round batch_of(const std::string& request) {
    std::string text = "[";
    for (int i = 0; i < kBatch; ++i) {
        text += (i > 0 ? "," : "") + request;
    }
    return {text + "]\n", 1};
}

// The read-only API, one method a round (docs/api.md, "Methods").
Round every_method(unsigned round) {
    static const std::array<std::string, 9> methods = {
        one("status"),
        one("attitude"),
        one("captures", R"({"limit":1000})"),
        one("get_settings"),
        one("limits"),
        one("subscribe", R"({"topics":["link","motion","captures"]})"),
        one("unsubscribe", R"({"topics":["link","motion","captures"]})"),
        one("attitude_channel"),
        one("photo", R"({"meta":{"n":1}})"),  // refused: read-only
    };
    if (round % (methods.size() + 1) == methods.size()) {
        return batch_of(one("captures", R"({"limit":800})"));
    }
    return {methods[round % (methods.size() + 1)] + "\n", 1};
}

// The vehicle's source gone wrong (a bridge in a loop): publish_vehicle back
// to back, each sample 1 ms of boot time after the last, so that every one
// is taken, moving north at 15 m/s; the UTC with every 10th; and every 50th
// round a photo, stamped against the track that moves under it.
Round vehicle_report(unsigned round) {
    if (round % 50 == 49) {
        return {one("photo") + "\n", 1};
    }
    const unsigned long long boot_ms = 1000ULL + round;
    char position[320];
    std::snprintf(position, sizeof position,
                  R"({"boot_ms":%llu,"lat":%.7f,"lon":8.5456,"alt_msl_m":488.0,)"
                  R"("velocity_ned":[15,0,0],"heading_deg":0,"fix":3,"h_acc_m":0.8})",
                  boot_ms, 47.3978 + round * 1.35e-7);
    std::string params = std::string(R"({"position":)") + position;
    if (round % 10 == 0) {
        params += R"(,"time":{"boot_ms":)" + std::to_string(boot_ms) + R"(,"utc_us":)" +
                  std::to_string(1'763'770'000'000'000ULL + boot_ms * 1000ULL) + "}";
    }
    return {one("publish_vehicle", params + "}") + "\n", 1};
}

Round round_of(FloodKind kind, unsigned round) {
    switch (kind) {
        case FloodKind::kPhoto:
            return {one("photo", R"({"meta":)" + kilobyte_meta() + "}") + "\n", 1};
        case FloodKind::kCaptures:
            return {one("captures", R"({"limit":1000})") + "\n", 1};
        case FloodKind::kBatches:
            return batch_of(one("captures", R"({"limit":800})"));
        case FloodKind::kEvery:
            return every_method(round);
        case FloodKind::kVehicle:
            return vehicle_report(round);
    }
    return {};
}

void drop_to(uid_t uid) {
    if (uid == 0) {
        return;
    }
    const gid_t gid = uid;
    if (::setgroups(0, nullptr) != 0 || ::setgid(gid) != 0 || ::setuid(uid) != 0) {
        throw std::runtime_error(std::string("cannot become uid ") + std::to_string(uid) + ": " +
                                 std::strerror(errno));
    }
}

// One connection: a round out, its replies (lines) counted back in.
struct FloodConn {
    Fd fd;
    std::string pending;
    int owed = 0;
    unsigned round = 0;
};

// False when the connection is gone (it is opened again).
bool send_round(FloodConn& f, FloodKind kind) {
    const Round r = round_of(kind, f.round++);
    f.owed = r.replies;
    return write_all(f.fd.get(), r.text, 60'000);
}

// Reads what arrived; every whole line is one reply (notifications count
// too: they only make the next round come sooner). False when gportd closed
// the connection (a reply over the client's queue limit does that).
bool drain(FloodConn& f, FloodKind kind) {
    std::array<char, 65536> buf{};
    const auto n = ::read(f.fd.get(), buf.data(), buf.size());
    if (n == 0 || (n < 0 && errno != EAGAIN && errno != EINTR)) {
        return false;
    }
    for (ssize_t i = 0; i < n; ++i) {
        if (buf[static_cast<std::size_t>(i)] == '\n' && --f.owed == 0 && !send_round(f, kind)) {
            return false;
        }
    }
    return true;
}

// A hostile client comes back: a closed connection is opened again at once.
void reconnect(FloodConn& f, FloodKind kind, const std::string& socket) {
    f.fd = connect_unix(socket);
    f.pending.clear();
    send_round(f, kind);  // a failure shows as a hang-up at the next poll
}

[[noreturn]] void flood(std::vector<FloodConn>& conns, FloodKind kind, const std::string& socket) {
    std::vector<pollfd> fds;
    for (auto& f : conns) {
        send_round(f, kind);  // as in reconnect()
        fds.push_back({f.fd.get(), POLLIN, 0});
    }
    for (;;) {
        if (::poll(fds.data(), fds.size(), 1000) < 0 && errno != EINTR) {
            throw std::runtime_error("flood: poll failed");
        }
        for (std::size_t i = 0; i < fds.size(); ++i) {
            if (fds[i].revents != 0 && !drain(conns[i], kind)) {
                reconnect(conns[i], kind, socket);
                fds[i].fd = conns[i].fd.get();
            }
        }
    }
}

}  // namespace

bool parse_flood_kind(const std::string& name, FloodKind& kind) {
    for (auto k : {FloodKind::kPhoto, FloodKind::kCaptures, FloodKind::kBatches, FloodKind::kEvery,
                   FloodKind::kVehicle}) {
        if (name == to_string(k)) {
            kind = k;
            return true;
        }
    }
    return false;
}

const char* to_string(FloodKind kind) {
    switch (kind) {
        case FloodKind::kPhoto:
            return "photo";
        case FloodKind::kCaptures:
            return "captures";
        case FloodKind::kBatches:
            return "batches";
        case FloodKind::kEvery:
            return "every";
        case FloodKind::kVehicle:
            return "vehicle";
    }
    return "?";
}

std::string kilobyte_meta() {
    return R"({"note":")" + std::string(1000, 'm') + R"("})";
}

int flood_child_main(int argc, char** argv) {
    if (argc < 5) {
        return 64;
    }
    FloodKind kind{};
    const int report = std::atoi(argv[4]);
    try {
        if (!parse_flood_kind(argv[1], kind)) {
            throw std::runtime_error(std::string("unknown flood ") + argv[1]);
        }
        std::signal(SIGPIPE, SIG_IGN);  // a closed connection is an error return, not a death
        drop_to(static_cast<uid_t>(std::strtoul(argv[3], nullptr, 10)));
        std::vector<FloodConn> conns(static_cast<std::size_t>(std::atoi(argv[2])));
        for (auto& f : conns) {
            f.fd = connect_unix(argv[0]);
        }
        [[maybe_unused]] const auto n = ::write(report, "ok\n", 3);
        ::close(report);
        flood(conns, kind, argv[0]);
    } catch (const std::exception& e) {
        const std::string line = std::string("error ") + e.what() + "\n";
        [[maybe_unused]] const auto n = ::write(report, line.data(), line.size());
        return 1;
    }
}

FloodProcess::FloodProcess(const std::string& socket, FloodKind kind, int connections, uid_t uid) {
    auto child = spawn_self({"bench_e2e", "--flood-child", socket, to_string(kind),
                             std::to_string(connections), std::to_string(uid), "3"},
                            "flood");
    child_ = std::move(child);
    std::string pending;
    std::string line;
    if (!read_line(child_->report(), pending, line, 30'000) || line != "ok") {
        stop();
        throw std::runtime_error("flood (" + std::string(to_string(kind)) + "): " + line);
    }
}

FloodProcess::~FloodProcess() {
    stop();
}

void FloodProcess::stop() {
    child_.reset();  // SIGKILL, and reaped
}

}  // namespace gport::bench
