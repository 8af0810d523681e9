#include "gport/mavlink/bridge/options.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "gport/base/exit_status.hpp"
#include "gport/version.hpp"

namespace gport::mavlink::bridge {

namespace {

using Json = nlohmann::json;

constexpr std::array<std::string_view, 7> kLogLevels = {"trace", "debug",    "info", "warn",
                                                        "error", "critical", "off"};

bool valid_number(const std::string& text, unsigned long max, unsigned& out) {
    if (text.empty() || text.size() > 9 ||
        !std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; })) {
        return false;
    }
    const unsigned long value = std::stoul(text);
    if (value == 0 || value > max) {
        return false;
    }
    out = static_cast<unsigned>(value);
    return true;
}

// Checks the values both sources share; empty when all is well.
std::string check(const Options& o) {
    if (!(o.attitude_rate_hz >= 0.1 && o.attitude_rate_hz <= 100)) {
        return "attitude rate = " + std::to_string(o.attitude_rate_hz) +
               " Hz is out of range; allowed 0.1 to 100";
    }
    if (o.lease_ms < 50 || o.lease_ms > 60000) {
        return "lease = " + std::to_string(o.lease_ms) + " ms is out of range; allowed 50 to 60000";
    }
    if (std::find(kLogLevels.begin(), kLogLevels.end(), o.log_level) == kLogLevels.end()) {
        return "log level \"" + o.log_level +
               "\" is unknown; allowed trace, debug, info, warn, error, critical, off";
    }
    if (o.socket.empty()) {
        return "the socket path is empty";
    }
    return {};
}

template <typename T>
void take(const Json& section, const char* key, T& out) {
    if (section.contains(key)) {
        out = section.at(key).get<T>();
    }
}

// Applies the `mavlink` section of a config file; returns the error text.
std::string apply_config(const std::string& path, Options& o) {
    std::ifstream in(path);
    if (!in) {
        return path + ": cannot be read";
    }
    try {
        const Json root = Json::parse(in, nullptr, true, /*ignore_comments=*/true);
        if (!root.is_object() || !root.contains("mavlink")) {
            return path + ": no \"mavlink\" section (an object) at the top level";
        }
        const Json& m = root.at("mavlink");
        static const std::array<std::string_view, 8> kKeys = {
            "socket",           "url",      "sysid",     "compid",
            "attitude_rate_hz", "lease_ms", "log_level", "invert"};
        for (const auto& [key, value] : m.items()) {
            if (std::find(kKeys.begin(), kKeys.end(), key) == kKeys.end()) {
                return path + ": mavlink." + key +
                       " is unknown; allowed socket, url, sysid, compid, attitude_rate_hz, "
                       "lease_ms, log_level, invert";
            }
        }
        take(m, "socket", o.socket);
        if (m.contains("url")) {
            std::string error;
            auto endpoint = parse_endpoint(m.at("url").get<std::string>(), error);
            if (!endpoint) {
                return path + ": mavlink.url: " + error;
            }
            o.mavlink = *endpoint;
        }
        if (m.contains("sysid")) {
            const int id = m.at("sysid").get<int>();
            if (id < 1 || id > 255) {
                return path + ": mavlink.sysid = " + std::to_string(id) +
                       " is out of range; allowed 1 to 255";
            }
            o.sysid = static_cast<std::uint8_t>(id);
        }
        if (m.contains("compid")) {
            const int id = m.at("compid").get<int>();
            if (id < 1 || id > 255) {
                return path + ": mavlink.compid = " + std::to_string(id) +
                       " is out of range; allowed 1 to 255";
            }
            o.compid = static_cast<std::uint8_t>(id);
        }
        take(m, "attitude_rate_hz", o.attitude_rate_hz);
        take(m, "lease_ms", o.lease_ms);
        take(m, "log_level", o.log_level);
        if (m.contains("invert")) {
            const Json& inv = m.at("invert");
            take(inv, "roll", o.invert.roll);
            take(inv, "pitch", o.invert.pitch);
            take(inv, "yaw", o.invert.yaw);
        }
    } catch (const Json::exception& e) {
        return path + ": " + e.what();
    }
    const std::string problem = check(o);
    return problem.empty() ? problem : path + ": " + problem;
}

}  // namespace

std::optional<Endpoint> parse_endpoint(const std::string& url, std::string& error) {
    const auto first = url.find(':');
    const auto last = url.rfind(':');
    const std::string allowed = "; allowed udpin:ADDR:PORT, udpout:ADDR:PORT, serial:DEVICE:BAUD";
    if (first == std::string::npos || first == last) {
        error = "\"" + url + "\" is not a MAVLink URL" + allowed;
        return std::nullopt;
    }
    const std::string scheme = url.substr(0, first);
    Endpoint e;
    e.address = url.substr(first + 1, last - first - 1);
    const std::string number = url.substr(last + 1);
    if (scheme == "udpin" || scheme == "udpout") {
        e.kind = scheme == "udpin" ? Endpoint::Kind::kUdpIn : Endpoint::Kind::kUdpOut;
        if (!valid_number(number, 65535, e.number)) {
            error = "port \"" + number + "\" in \"" + url + "\" is not 1 to 65535";
            return std::nullopt;
        }
    } else if (scheme == "serial") {
        e.kind = Endpoint::Kind::kSerial;
        if (!valid_number(number, 4000000, e.number)) {
            error = "baud rate \"" + number + "\" in \"" + url + "\" is not 1 to 4000000";
            return std::nullopt;
        }
    } else {
        error = "scheme \"" + scheme + "\" of \"" + url + "\" is unknown" + allowed;
        return std::nullopt;
    }
    if (e.address.empty()) {
        error = "\"" + url + "\" has no address or device" + allowed;
        return std::nullopt;
    }
    return e;
}

std::string to_string(const Endpoint& e) {
    const char* scheme = e.kind == Endpoint::Kind::kUdpIn    ? "udpin"
                         : e.kind == Endpoint::Kind::kUdpOut ? "udpout"
                                                             : "serial";
    return std::string(scheme) + ":" + e.address + ":" + std::to_string(e.number);
}

ParseOutcome parse_options(const std::vector<std::string>& argv, const std::string& env_socket) {
    CLI::App app{"gport-mavlink: the G-Port, served by gportd, as a MAVLink gimbal v2 device",
                 "gport-mavlink"};
    app.set_version_flag("--version", std::string("gport-mavlink ") + std::string(gport::kVersion));
    std::optional<std::string> socket, url, config, log_level;
    std::optional<int> sysid, compid;
    std::optional<double> rate;
    std::optional<unsigned> lease;
    bool inv_roll = false, inv_pitch = false, inv_yaw = false;
    app.add_option("--socket", socket,
                   "gportd's socket (default /run/gportd.sock, or $GPORT_SOCKET)");
    app.add_option(
        "--mavlink", url,
        "udpin:ADDR:PORT, udpout:ADDR:PORT or serial:DEVICE:BAUD (default udpin:0.0.0.0:14550)");
    app.add_option("--sysid", sysid, "system id (default: the first autopilot heartbeat's)")
        ->check(CLI::Range(1, 255));
    app.add_option("--compid", compid, "component id (default 154, MAV_COMP_ID_GIMBAL)")
        ->check(CLI::Range(1, 255));
    app.add_option("--attitude-rate", rate,
                   "GIMBAL_DEVICE_ATTITUDE_STATUS rate in Hz (0.1 to 100, default 10)");
    app.add_option("--lease-ms", lease, "speed lease in ms (50 to 60000, default 500)");
    app.add_option("--log-level", log_level, "trace, debug, info, warn, error, critical, off");
    app.add_option("--config", config, "a JSON file whose \"mavlink\" section sets these options");
    app.add_flag("--invert-roll", inv_roll, "flip the roll axis's sign");
    app.add_flag("--invert-pitch", inv_pitch, "flip the pitch axis's sign");
    app.add_flag("--invert-yaw", inv_yaw, "flip the yaw axis's sign");
    std::vector<std::string> args(argv.rbegin(), argv.rend() - 1);  // CLI11 wants them reversed
    ParseOutcome out;
    try {
        app.parse(args);
    } catch (const CLI::Success& e) {
        std::ostringstream text;
        out.exit_code = app.exit(e, text, text);
        out.text = text.str();
        return out;
    } catch (const CLI::ParseError& e) {
        out.exit_code = kExitUsage;
        out.text = "gport-mavlink: " + std::string(e.what()) + "\nTry 'gport-mavlink --help'.\n";
        return out;
    }
    Options o;
    if (!env_socket.empty()) {
        o.socket = env_socket;
    }
    if (config) {
        if (auto problem = apply_config(*config, o); !problem.empty()) {
            out.exit_code = kExitConfig;
            out.text = "gport-mavlink: configuration error: " + problem + "\n";
            return out;
        }
    }
    if (url) {
        std::string error;
        auto endpoint = parse_endpoint(*url, error);
        if (!endpoint) {
            out.exit_code = kExitUsage;
            out.text = "gport-mavlink: --mavlink: " + error + "\n";
            return out;
        }
        o.mavlink = *endpoint;
    }
    if (socket)
        o.socket = *socket;
    if (sysid)
        o.sysid = static_cast<std::uint8_t>(*sysid);
    if (compid)
        o.compid = static_cast<std::uint8_t>(*compid);
    if (rate)
        o.attitude_rate_hz = *rate;
    if (lease)
        o.lease_ms = *lease;
    if (log_level)
        o.log_level = *log_level;
    o.invert.roll = o.invert.roll || inv_roll;
    o.invert.pitch = o.invert.pitch || inv_pitch;
    o.invert.yaw = o.invert.yaw || inv_yaw;
    if (auto problem = check(o); !problem.empty()) {
        out.exit_code = kExitUsage;
        out.text = "gport-mavlink: " + problem + "\n";
        return out;
    }
    out.options = o;
    return out;
}

}  // namespace gport::mavlink::bridge
