#include "gport/mavlink/bridge/options.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <sstream>

#include "gport/base/args.hpp"
#include "gport/base/exit_status.hpp"
#include "gport/client/client.hpp"
#include "options_internal.hpp"

namespace gport::mavlink::bridge {

namespace {

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

// A system id (detail::mavlink_id) written in decimal digits.
std::optional<std::uint8_t> sysid_of(std::string_view text) {
    unsigned id = 0;
    if (!valid_number(std::string(text), 999, id)) {
        return std::nullopt;
    }
    return detail::mavlink_id(id);
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

bool parse_sysid(std::string_view text, std::optional<std::uint8_t>& out, std::string& error) {
    if (text == "auto") {
        out.reset();
        return true;
    }
    if (auto id = sysid_of(text)) {
        out = *id;
        return true;
    }
    error = "expected a system id from 1 to 255, or auto";
    return false;
}

std::optional<std::vector<std::uint8_t>> parse_sysid_list(std::string_view text,
                                                          std::string& error) {
    std::vector<std::uint8_t> ids;
    if (text == "none") {
        return ids;
    }
    while (true) {
        const auto comma = text.find(',');
        const auto item = text.substr(0, comma);
        const auto id = sysid_of(item);
        if (!id) {
            error = "\"" + std::string(item) +
                    "\" is not a system id; expected system ids from 1 to 255 separated by "
                    "commas (255,250), or none";
            return std::nullopt;
        }
        ids.push_back(*id);
        if (comma == std::string_view::npos) {
            return ids;
        }
        text.remove_prefix(comma + 1);
    }
}

std::string to_string(const std::vector<std::uint8_t>& sysids) {
    if (sysids.empty()) {
        return "none";
    }
    std::string out;
    for (auto id : sysids) {
        if (!out.empty()) {
            out += ',';
        }
        out += std::to_string(id);  // appended, not "," + ...: GCC 12's -Wrestrict (armhf)
    }
    return out;
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
    "Trust: commands are taken only from the vehicle's system id (--sysid) and the\n"
    "ground stations' (--gcs-sysid); with --signing-key only from correctly signed\n"
    "frames (docs/mavlink.md, \"Security\").\n\n"
    "Exit status: 0 after SIGINT/SIGTERM (and for --help, --version), 64 for a bad\n"
    "command line, 71 when the MAVLink endpoint cannot be opened, 78 for a bad\n"
    "config file, signing key file or state directory.\n\n"
    "Examples:\n"
    "  gport-mavlink                                     # udpin:127.0.0.1:14560, mavlink-router\n"
    "  gport-mavlink --mavlink udpout:192.168.1.10:14550\n"
    "  gport-mavlink --mavlink serial:/dev/ttyAMA0:921600 --invert-yaw\n"
    "  gport-mavlink --signing-key /etc/gportd/mavlink.key --state-dir /var/lib/gport-mavlink\n"
    "  gport-mavlink --config /etc/gportd/mavlink.json";

std::optional<std::string> check_url(std::string_view text) {
    std::string error;
    if (parse_endpoint(std::string(text), error)) {
        return std::nullopt;
    }
    return error;
}

std::optional<std::string> check_sysid(std::string_view text) {
    std::string error;
    std::optional<std::uint8_t> id;
    if (parse_sysid(text, id, error)) {
        return std::nullopt;
    }
    return std::string(text) + ": " + error;
}

std::optional<std::string> check_sysid_list(std::string_view text) {
    std::string error;
    if (parse_sysid_list(text, error)) {
        return std::nullopt;
    }
    return std::string(text) + ": " + error;
}

std::optional<std::string> not_empty(std::string_view text) {
    if (text.empty()) {
        return std::string("must not be empty");
    }
    return std::nullopt;
}

// What the command line gave; empty for what it did not.
struct Given {
    std::optional<std::string> socket, url, config, log_level, sysid, gcs, key, state_dir;
    std::optional<int> compid;
    std::optional<double> rate;
    std::optional<unsigned> lease;
    bool inv_roll = false, inv_pitch = false, inv_yaw = false;
    bool no_camera = false;
};

void add_trust_options(CLI::App& app, Given& g) {
    app.add_option("--sysid", g.sysid,
                   "the vehicle's system id, 1 to 255, or auto: adopt the first autopilot "
                   "heartbeat's (spoofable) (default 1)")
        ->type_name("N|auto")
        ->check(args::check_with(check_sysid));
    app.add_option("--gcs-sysid", g.gcs,
                   "ground stations whose commands are taken too: ids separated by commas, or "
                   "none (default 255)")
        ->type_name("IDS")
        ->check(args::check_with(check_sysid_list));
    app.add_option("--signing-key", g.key,
                   "MAVLink 2 signing: a file (mode 600) with the 32-byte key as 64 hex digits; "
                   "then only signed frames are taken, and all sent are signed")
        ->type_name("FILE")
        ->check(args::check_with(not_empty));
    app.add_option("--state-dir", g.state_dir,
                   "where the signing timestamp is kept (default $STATE_DIRECTORY)")
        ->type_name("DIR")
        ->check(args::check_with(not_empty));
}

void add_options(CLI::App& app, Given& g) {
    app.add_option("--socket", g.socket,
                   "gportd's socket (default $GPORT_SOCKET, else /run/gportd.sock)")
        ->type_name("PATH")
        ->check(args::check_with(not_empty));
    app.add_option("--mavlink", g.url,
                   "udpin:ADDR:PORT, udpout:ADDR:PORT or serial:DEVICE:BAUD (default "
                   "udpin:127.0.0.1:14560)")
        ->type_name("URL")
        ->check(args::check_with(check_url));
    add_trust_options(app, g);
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
    app.add_option("--log-level", g.log_level,
                   "what to log, to the journal or stderr (default info)")
        ->type_name("LEVEL")
        ->check(args::one_of({detail::kLogLevels.begin(), detail::kLogLevels.end()}));
    app.add_option("--config", g.config, "a JSON file whose \"mavlink\" section sets these options")
        ->type_name("FILE");
    app.add_flag("--invert-roll", g.inv_roll, "flip the roll axis's sign");
    app.add_flag("--invert-pitch", g.inv_pitch, "flip the pitch axis's sign");
    app.add_flag("--invert-yaw", g.inv_yaw, "flip the yaw axis's sign");
    app.add_flag("--no-camera", g.no_camera,
                 "no MAVLink camera component (compid 100): no camera heartbeat, its commands "
                 "unanswered");
}

ParseOutcome usage_error(const std::string& problem) {
    ParseOutcome out;
    out.exit_code = kExitUsage;
    out.text = "gport-mavlink: " + problem + "\nTry 'gport-mavlink --help'.\n";
    return out;
}

ParseOutcome failure(int code, const std::string& text) {
    ParseOutcome out;
    out.exit_code = code;
    out.text = "gport-mavlink: " + text + "\n";
    return out;
}

// The command line's values over `o` (the config's over the defaults).
void apply_given(const Given& given, Options& o) {
    std::string ignored;  // every value was checked by its option
    if (given.url) {
        o.mavlink = *parse_endpoint(*given.url, ignored);
    }
    if (given.sysid) {
        parse_sysid(*given.sysid, o.sysid, ignored);
    }
    if (given.gcs) {
        o.gcs_sysids = *parse_sysid_list(*given.gcs, ignored);
    }
    o.socket = given.socket.value_or(o.socket);
    o.signing_key = given.key.value_or(o.signing_key);
    o.state_dir = given.state_dir.value_or(o.state_dir);
    if (given.compid) {
        o.compid = static_cast<std::uint8_t>(*given.compid);
    }
    o.attitude_rate_hz = given.rate.value_or(o.attitude_rate_hz);
    o.lease_ms = given.lease.value_or(o.lease_ms);
    o.log_level = given.log_level.value_or(o.log_level);
    o.invert.roll = o.invert.roll || given.inv_roll;
    o.invert.pitch = o.invert.pitch || given.inv_pitch;
    o.invert.yaw = o.invert.yaw || given.inv_yaw;
    o.camera = o.camera && !given.no_camera;
}

ParseOutcome finish(const Given& given, const Environment& env) {
    Options o;
    o.socket = client::Client::default_socket(env.socket.c_str());
    // systemd sets STATE_DIRECTORY to the StateDirectory= paths, ':'-separated.
    o.state_dir = env.state_directory.substr(0, env.state_directory.find(':'));
    if (given.config) {
        if (auto problem = detail::apply_config(*given.config, o); !problem.empty()) {
            return failure(kExitConfig, "configuration error: " + problem);
        }
    }
    apply_given(given, o);
    if (auto problem = detail::check(o); !problem.empty()) {
        return failure(kExitUsage, problem);
    }
    if (!o.signing_key.empty() && o.state_dir.empty()) {
        return failure(given.key ? kExitUsage : kExitConfig,
                       "the signing key " + o.signing_key +
                           " needs a state directory to keep the signing timestamp in; "
                           "give --state-dir DIR, the config key state_dir, or run under "
                           "systemd with StateDirectory= ($STATE_DIRECTORY)");
    }
    ParseOutcome out;
    out.options = o;
    return out;
}

}  // namespace

ParseOutcome parse_options(const std::vector<std::string>& argv, const Environment& env) {
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
    return finish(given, env);
}

}  // namespace gport::mavlink::bridge
