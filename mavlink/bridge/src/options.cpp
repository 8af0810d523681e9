#include "gport/mavlink/bridge/options.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "gport/base/args.hpp"
#include "gport/base/exit_status.hpp"

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

namespace {

constexpr const char* kDescription =
    "gport-mavlink: the G-Port, served by gportd, as a MAVLink gimbal v2 device.\n"
    "A client of gportd's socket: it streams GIMBAL_DEVICE_ATTITUDE_STATUS, answers\n"
    "GIMBAL_DEVICE_INFORMATION and turns GIMBAL_DEVICE_SET_ATTITUDE and the photo\n"
    "and video commands into gportd calls (man gport-mavlink, docs/mavlink.md).";

constexpr const char* kFooter =
    "Options on the command line win over the \"mavlink\" section of --config,\n"
    "which wins over the defaults.\n\n"
    "Exit status: 0 after SIGINT/SIGTERM (and for --help, --version), 64 for a bad\n"
    "command line, 71 when the MAVLink endpoint cannot be opened, 78 for a bad\n"
    "config file.\n\n"
    "Examples:\n"
    "  gport-mavlink --mavlink udpin:127.0.0.1:14560    # behind mavlink-router\n"
    "  gport-mavlink --mavlink udpout:192.168.1.10:14550\n"
    "  gport-mavlink --mavlink serial:/dev/ttyAMA0:921600 --invert-yaw\n"
    "  gport-mavlink --config /etc/gportd/mavlink.json";

std::optional<std::string> check_url(std::string_view text) {
    std::string error;
    if (parse_endpoint(std::string(text), error)) {
        return std::nullopt;
    }
    return error;
}

std::optional<std::string> not_empty(std::string_view text) {
    if (text.empty()) {
        return std::string("must not be empty");
    }
    return std::nullopt;
}

// What the command line gave; empty for what it did not.
struct Given {
    std::optional<std::string> socket, url, config, log_level;
    std::optional<int> sysid, compid;
    std::optional<double> rate;
    std::optional<unsigned> lease;
    bool inv_roll = false, inv_pitch = false, inv_yaw = false;
};

void add_options(CLI::App& app, Given& g) {
    app.add_option("--socket", g.socket,
                   "gportd's socket (default $GPORT_SOCKET, else /run/gportd.sock)")
        ->type_name("PATH")
        ->check(args::check_with(not_empty));
    app.add_option("--mavlink", g.url,
                   "udpin:ADDR:PORT, udpout:ADDR:PORT or serial:DEVICE:BAUD (default "
                   "udpin:0.0.0.0:14550)")
        ->type_name("URL")
        ->check(args::check_with(check_url));
    app.add_option("--sysid", g.sysid, "system id (default: the first autopilot heartbeat's)")
        ->type_name("N")
        ->check(args::integer_in(1, 255));
    app.add_option("--compid", g.compid, "component id (default 154, MAV_COMP_ID_GIMBAL)")
        ->type_name("N")
        ->check(args::integer_in(1, 255));
    app.add_option("--attitude-rate", g.rate,
                   "GIMBAL_DEVICE_ATTITUDE_STATUS messages per second (default 10)")
        ->type_name("HZ")
        ->check(args::number_in(0.1, 100, "messages per second"));
    app.add_option("--lease-ms", g.lease, "the lease of each speed sent to gportd (default 500)")
        ->type_name("MS")
        ->check(args::integer_in(50, 60000));
    app.add_option("--log-level", g.log_level, "what to log to stderr (default info)")
        ->type_name("LEVEL")
        ->check(args::one_of({kLogLevels.begin(), kLogLevels.end()}));
    app.add_option("--config", g.config, "a JSON file whose \"mavlink\" section sets these options")
        ->type_name("FILE");
    app.add_flag("--invert-roll", g.inv_roll, "flip the roll axis's sign");
    app.add_flag("--invert-pitch", g.inv_pitch, "flip the pitch axis's sign");
    app.add_flag("--invert-yaw", g.inv_yaw, "flip the yaw axis's sign");
}

ParseOutcome usage_error(const std::string& problem) {
    ParseOutcome out;
    out.exit_code = kExitUsage;
    out.text = "gport-mavlink: " + problem + "\nTry 'gport-mavlink --help'.\n";
    return out;
}

ParseOutcome finish(const Given& given, const std::string& env_socket) {
    ParseOutcome out;
    Options o;
    if (!env_socket.empty()) {
        o.socket = env_socket;
    }
    if (given.config) {
        if (auto problem = apply_config(*given.config, o); !problem.empty()) {
            out.exit_code = kExitConfig;
            out.text = "gport-mavlink: configuration error: " + problem + "\n";
            return out;
        }
    }
    if (given.url) {
        std::string error;
        auto endpoint = parse_endpoint(*given.url, error);
        if (!endpoint) {
            out.exit_code = kExitUsage;
            out.text = "gport-mavlink: --mavlink: " + error + "\n";
            return out;
        }
        o.mavlink = *endpoint;
    }
    if (given.socket) {
        o.socket = *given.socket;
    }
    if (given.sysid) {
        o.sysid = static_cast<std::uint8_t>(*given.sysid);
    }
    if (given.compid) {
        o.compid = static_cast<std::uint8_t>(*given.compid);
    }
    if (given.rate) {
        o.attitude_rate_hz = *given.rate;
    }
    if (given.lease) {
        o.lease_ms = *given.lease;
    }
    if (given.log_level) {
        o.log_level = *given.log_level;
    }
    o.invert.roll = o.invert.roll || given.inv_roll;
    o.invert.pitch = o.invert.pitch || given.inv_pitch;
    o.invert.yaw = o.invert.yaw || given.inv_yaw;
    if (auto problem = check(o); !problem.empty()) {
        out.exit_code = kExitUsage;
        out.text = "gport-mavlink: " + problem + "\n";
        return out;
    }
    out.options = o;
    return out;
}

}  // namespace

ParseOutcome parse_options(const std::vector<std::string>& argv, const std::string& env_socket) {
    CLI::App app{kDescription, "gport-mavlink"};
    args::configure(app, kFooter);
    app.allow_extras();  // named by args::leftover_problem
    Given given;
    add_options(app, given);
    std::vector<std::string> reversed(argv.rbegin(), argv.rend() - 1);  // CLI11 wants them reversed
    ParseOutcome out;
    try {
        app.parse(reversed);
    } catch (const CLI::ParseError& e) {
        if (!args::is_request(e)) {
            return usage_error(args::message_of(e));
        }
        std::ostringstream text;
        out.exit_code = app.exit(e, text, text);
        out.text = text.str();
        return out;
    }
    if (auto problem = args::leftover_problem(app); !problem.empty()) {
        return usage_error(problem);
    }
    return finish(given, env_socket);
}

}  // namespace gport::mavlink::bridge
