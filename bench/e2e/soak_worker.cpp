#include "soak_worker.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace gport::bench {

std::int64_t Worker::after_ms(std::int64_t t_ns, int low, int high) {
    return t_ns + std::int64_t{std::uniform_int_distribution<int>(low, high)(rng_)} * 1'000'000;
}

double Worker::uniform(double low, double high) {
    return std::uniform_real_distribution<double>(low, high)(rng_);
}

std::uint64_t Worker::act(std::int64_t t_ns, WorkerTally& tally) {
    if (t_ns < next_ns_) {
        return 0;
    }
    if (!connected()) {
        connect(t_ns, tally);
        return 0;
    }
    if (broken_) {
        const auto id = disconnect(tally);
        next_ns_ = after_ms(t_ns, 100, 2000);
        return id;
    }
    if (id_ == 0) {  // still waiting for its own status reply
        next_ns_ = after_ms(t_ns, 20, 50);
        return 0;
    }
    // One time in eight the client goes away, abruptly, whatever it was doing.
    if (std::uniform_int_distribution<int>(0, 7)(rng_) == 0) {
        const auto id = disconnect(tally);
        next_ns_ = after_ms(t_ns, 100, 2000);
        return id;
    }
    random_request(t_ns, tally);
    next_ns_ = after_ms(t_ns, 50, 800);
    return broken_ ? disconnect(tally) : 0;
}

void Worker::connect(std::int64_t t_ns, WorkerTally& tally) {
    try {
        fd_ = connect_unix(socket_);
    } catch (const std::runtime_error&) {
        next_ns_ = after_ms(t_ns, 200, 1000);  // the daemon may be full; try later
        return;
    }
    ++tally.connects;
    id_ = 0;
    pending_.clear();
    stalled_until_ = 0;
    send("status", "", tally);
    next_ns_ = after_ms(t_ns, 20, 50);
}

std::uint64_t Worker::disconnect(WorkerTally& tally) {
    if (!connected()) {
        return 0;
    }
    fd_.reset();
    broken_ = false;
    holds_control_ = false;
    ++tally.disconnects;
    const auto id = id_;
    id_ = 0;
    return id;
}

void Worker::random_request(std::int64_t t_ns, WorkerTally& tally) {
    const int pick = std::uniform_int_distribution<int>(0, 99)(rng_);
    if (pick < 25) {  // speed, usually with a duration
        const auto duration = std::uniform_int_distribution<int>(100, 5000)(rng_);
        send("speed",
             fmt::format(R"({{"roll":{:.2f},"pitch":{:.2f},"yaw":{:.2f}{}}})", uniform(-20, 20),
                         uniform(-20, 20), uniform(-60, 60),
                         pick < 20 ? fmt::format(R"(,"duration_ms":{})", duration) : ""),
             tally);
    } else if (pick < 33) {
        send("stop", "", tally);
    } else if (pick < 40) {
        send("angle",
             fmt::format(R"({{"roll":{:.2f},"pitch":{:.2f},"yaw":{:.2f}}})", uniform(-40, 40),
                         uniform(-80, 80), uniform(-160, 160)),
             tally);
    } else if (pick < 43) {
        send(pick == 41 ? "lock" : "center", "", tally);
    } else if (pick < 48) {
        send("get_settings", "", tally);
    } else if (pick < 52) {
        send("set_settings",
             fmt::format(R"({{"dead_zone":{},"follow_speed":{}}})",
                         std::uniform_int_distribution<int>(0, 255)(rng_),
                         std::uniform_int_distribution<int>(0, 255)(rng_)),
             tally);
    } else if (pick < 64) {
        send("subscribe",
             pick < 60 ? R"({"topics":["attitude","link","motion"]})"
                       : R"({"topics":["attitude"],"max_rate_hz":5})",
             tally);
    } else if (pick < 69) {
        send("unsubscribe", R"({"topics":["attitude"]})", tally);
    } else if (pick < 79) {
        send(pick < 77 ? "status" : "attitude", "", tally);
    } else if (pick < 81) {
        send(pick == 80 ? "photo" : "record", "", tally);
    } else if (pick < 83) {
        // Control is held rarely and briefly: a holder makes everyone else's
        // commands fail (-32003), which would leave little motion to stop.
        if (holds_control_) {
            send("release", "", tally);
            holds_control_ = false;
        } else if (std::uniform_int_distribution<int>(0, 9)(rng_) == 0) {
            send("acquire", "", tally);
            holds_control_ = true;
        } else {
            send("status", "", tally);
        }
    } else if (pick < 86) {
        stalled_until_ = after_ms(t_ns, 1000, 6000);  // stop reading for a while
    } else {
        send("status", "", tally);
    }
}

void Worker::send(const std::string& method, const std::string& params, WorkerTally& tally) {
    std::string line =
        fmt::format(R"({{"jsonrpc":"2.0","id":{},"method":"{}")", next_request_++, method);
    if (!params.empty()) {
        line += R"(,"params":)" + params;
    }
    line += "}\n";
    ++tally.requests;
    // A stalled worker's socket may fill up: give up quickly rather than block the loop.
    if (!write_all(fd_.get(), line, 20)) {
        broken_ = true;
        ++tally.refused;
    }
}

bool Worker::on_readable(WorkerTally& tally) {
    char buffer[65536];
    while (true) {
        const auto n = ::read(fd_.get(), buffer, sizeof(buffer));
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n < 0 && errno == EAGAIN) {
            break;
        }
        if (n <= 0) {
            return false;
        }
        pending_.append(buffer, static_cast<std::size_t>(n));
    }
    std::size_t start = 0;
    for (auto nl = pending_.find('\n'); nl != std::string::npos; nl = pending_.find('\n', start)) {
        on_line(pending_.substr(start, nl - start), tally);
        start = nl + 1;
    }
    pending_.erase(0, start);
    return true;
}

void Worker::on_line(const std::string& line, WorkerTally& tally) {
    if (line.starts_with(R"({"jsonrpc":"2.0","method":"attitude")")) {
        ++tally.attitude_lines;
        return;
    }
    if (line.find(R"("method":)") != std::string::npos) {
        return;  // link and motion notifications
    }
    ++tally.replies;
    const auto reply = nlohmann::json::parse(line, nullptr, false);
    if (reply.is_discarded()) {
        tally.errors[-1]++;  // not JSON: counted as our own error code -1
        return;
    }
    if (reply.contains("error")) {
        tally.errors[reply["error"].value("code", 0)]++;
        return;
    }
    if (id_ == 0 && reply.contains("result") && reply["result"].contains("client")) {
        id_ = reply["result"]["client"].value("id", std::uint64_t{0});
    }
}

}  // namespace gport::bench
