#include "gport/cli/output.hpp"

#include <fmt/format.h>
#include <time.h>

#include <regex>

#include "geotag.hpp"
#include "gport/cli/printable.hpp"
#include "gport/contract/limits.hpp"

namespace gport::cli {
namespace {

using nlohmann::json;

// Reads a member leniently: output must never throw on an unexpected shape.
template <typename T>
T get(const json& object, const char* key, T fallback) {
    if (!object.is_object()) {
        return fallback;
    }
    auto it = object.find(key);
    if (it == object.end() || it->is_null()) {
        return fallback;
    }
    try {
        return it->get<T>();
    } catch (const json::exception&) {
        return fallback;
    }
}

// A string member as printable text (gportd's words, a peer's text).
std::string word(const json& object, const char* key, const char* fallback) {
    return printable(get(object, key, std::string(fallback)));
}

// Any member as printable text: a string as it is, anything else as JSON.
std::string shown(const json& value) {
    return printable(value.is_string() ? value.get<std::string>() : json_line(value));
}

std::string axes(const json& a) {
    return fmt::format("roll {:.2f} pitch {:.2f} yaw {:.2f}", get(a, "roll", 0.0),
                       get(a, "pitch", 0.0), get(a, "yaw", 0.0));
}

std::string client(const json& c) {
    if (!c.is_object()) {
        return "nobody";
    }
    return fmt::format("pid {} (uid {}, client {})", get(c, "pid", 0), get(c, "uid", 0),
                       get(c, "id", 0));
}

std::string duration(long long ms) {
    const long long s = ms / 1000;
    if (s >= 3600) {
        return fmt::format("{}h {:02}m {:02}s", s / 3600, s / 60 % 60, s % 60);
    }
    if (s >= 60) {
        return fmt::format("{}m {:02}s", s / 60, s % 60);
    }
    return fmt::format("{:.1f}s", static_cast<double>(ms) / 1000.0);
}

std::string attitude(const json& a) {
    std::string out =
        fmt::format("seq {}  imu {}  hall {}", get(a, "seq", 0ull),
                    axes(a.value("imu", json::object())), axes(a.value("hall", json::object())));
    if (a.contains("rates")) {
        const auto& r = a["rates"];
        const auto imu = r.value("imu", json::object());
        out += fmt::format("  rates hall {}  imu x {:.2f} y {:.2f} z {:.2f}",
                           axes(r.value("hall", json::object())), get(imu, "x", 0.0),
                           get(imu, "y", 0.0), get(imu, "z", 0.0));
    }
    if (a.contains("dropped")) {
        out += fmt::format("  ({} dropped so far)", get(a, "dropped", 0ull));
    }
    return out;
}

std::string motion(const json& m) {
    if (!m.is_object()) {
        return "none";
    }
    if (m.contains("target")) {  // a tracked angle or centre motion
        return fmt::format("{} to {} deg, {} ms so far, owner {}", word(m, "mode", "?"),
                           axes(m["target"]), get(m, "elapsed_ms", 0ll),
                           client(m.value("owner", json())));
    }
    return fmt::format("{} {} deg/s, {} ms left, owner {}", word(m, "mode", "?"),
                       axes(m.value("speed", json::object())), get(m, "time_left_ms", 0ll),
                       client(m.value("owner", json())));
}

std::string status(const json& s) {
    const auto link = s.value("link", json::object());
    const auto c = s.value("counters", json::object());
    std::string out;
    out += fmt::format("link:      {} ({})\n", word(link, "state", "?"), word(link, "reason", ""));
    const auto error = word(s, "device_error", "");
    out += fmt::format("device:    {} ({})\n", word(s, "device", "?"),
                       get(s, "device_open", false) ? "open"
                       : error.empty()              ? "closed"
                                                    : "closed: " + error);
    out += fmt::format("daemon:    gportd {}, API {}, up {}\n", word(s, "daemon_version", "?"),
                       get(s, "api_version", 0), duration(get(s, "uptime_ms", 0ll)));
    const auto age = s.value("attitude_age_ms", json());
    out += fmt::format("attitude:  {}\n", age.is_number()
                                              ? fmt::format("{} ms old", age.get<long long>())
                                              : std::string("none received"));
    out += fmt::format("clients:   {}\n", get(s, "clients", 0));
    out += fmt::format("motion:    {}\n", motion(s.value("motion", json())));
    out += fmt::format("control:   {}\n", s.value("controller", json()).is_object()
                                              ? "held by " + client(s["controller"])
                                              : std::string("free (last command wins)"));
    out += fmt::format("recording: {} (assumed)\n", word(s, "recording", "unknown"));
    out +=
        fmt::format("frames:    in {} ({} bytes), out {} ({} bytes), attitude {}\n",
                    get(c, "frames_in", 0ull), get(c, "bytes_in", 0ull), get(c, "frames_out", 0ull),
                    get(c, "bytes_out", 0ull), get(c, "attitude_frames", 0ull));
    out += fmt::format("errors:    crc {}, header {}, resyncs {}, garbage bytes {}\n",
                       get(c, "crc_errors", 0ull), get(c, "header_errors", 0ull),
                       get(c, "resyncs", 0ull), get(c, "garbage_bytes", 0ull));
    out += fmt::format("dropped:   {} notifications in total\n",
                       get(s, "dropped_notifications", 0ull));
    return out;
}

// angle and center: "sent", what was clamped, and with --wait how it ended.
std::string position(const std::string& command, const json& result) {
    std::string out = fmt::format("{}: sent", command);
    if (result.contains("angle")) {
        out += " " + axes(result["angle"]) + " deg";
    }
    std::string clamped;
    for (const auto& axis : result.value("clamped", json::array())) {
        clamped += (clamped.empty() ? "" : ", ") + shown(axis);
    }
    if (!clamped.empty()) {
        out += " (clamped: " + clamped + ")";
    }
    out += "\n";
    const auto ended = result.value("ended", json());
    if (ended.is_object()) {
        const auto at = ended.value("attitude", json());
        out += fmt::format("ended: {} after {} ms; {}\n", word(ended, "reason", "?"),
                           get(ended, "elapsed_ms", 0ll),
                           at.is_object() ? "hall " + axes(at.value("hall", json::object()))
                                          : std::string("no attitude received"));
        if (ended.contains("detail")) {  // stalled: where the gimbal stopped
            out += word(ended, "detail", "") + "\n";
        }
    }
    return out;
}

std::string settings(const json& s) {
    return fmt::format("dead zone:     {}\nfollow speed:  {}\ninverted:      {}\n",
                       get(s, "dead_zone", 0), get(s, "follow_speed", 0),
                       get(s, "inverted", false) ? "yes" : "no");
}

// limits: one line per axis, then speed and margin; "no limit" for the
// protocol's whole range.
std::string limits(const json& l) {
    using contract::kMaxDegrees;
    std::string out;
    for (const auto* axis : {"roll", "pitch", "yaw"}) {
        const auto range = l.value(axis, json::object());
        const double min = get(range, "min", -kMaxDegrees);
        const double max = get(range, "max", kMaxDegrees);
        out += fmt::format("{:<16}{} to {} deg{}\n", std::string(axis) + ":", min, max,
                           min <= -kMaxDegrees && max >= kMaxDegrees ? " (no limit)" : "");
    }
    const double speed = get(l, "max_speed", kMaxDegrees);
    out += fmt::format("{:<16}{} deg/s{}\n", "max speed:", speed,
                       speed >= kMaxDegrees ? " (no limit)" : "");
    out += fmt::format("{:<16}{} deg\n", "braking margin:", get(l, "braking_margin_deg", 0.0));
    return out;
}

}  // namespace

std::string format_result(const std::string& command, const json& result) {
    if (command == "status") {
        return status(result);
    }
    if (command == "attitude") {
        return attitude(result) + fmt::format("  (age {} ms)\n", get(result, "age_ms", 0ll));
    }
    if (command == "settings") {
        return settings(result);
    }
    if (command == "limits") {
        return limits(result);
    }
    if (command == "angle" || command == "center") {
        return position(command, result);
    }
    if (command == "speed") {
        return fmt::format("moving for {} ms\n", get(result, "duration_ms", 0ll));
    }
    if (command == "watch") {
        std::string topics;
        for (const auto& t : result.value("topics", json::array())) {
            topics += (topics.empty() ? "" : ", ") + shown(t);
        }
        return fmt::format("watching {} (Ctrl-C to stop)\n", topics.empty() ? "nothing" : topics);
    }
    if (command == "record" && result.contains("recording")) {
        return fmt::format("record: {}{}; recording {} (assumed)\n",
                           get(result, "sent", true) ? "sent" : "nothing sent",
                           capture_suffix(result), word(result, "recording", "unknown"));
    }
    return fmt::format("{}: sent{}\n", command, capture_suffix(result));
}

std::string format_notification(const json& message) {
    const auto topic = word(message, "method", "?");
    const auto params = message.value("params", json::object());
    if (topic == "attitude") {
        return "attitude  " + attitude(params) + "\n";
    }
    if (topic == "link") {
        return fmt::format("link      {} ({})\n", word(params, "state", "?"),
                           word(params, "reason", ""));
    }
    if (topic == "motion") {
        std::string out =
            fmt::format("motion    {} {}", word(params, "change", "?"), word(params, "mode", "?"));
        if (params.contains("speed")) {
            out += " " + axes(params["speed"]) + " deg/s";
        }
        if (params.contains("target")) {
            out += " to " + axes(params["target"]) + " deg";
        } else if (params.contains("angle")) {
            out += " " + axes(params["angle"]) + " deg";
        }
        if (params.contains("reason")) {
            out += ", reason " + word(params, "reason", "?");
        }
        return out + ", owner " + client(params.value("owner", json())) + "\n";
    }
    return json_line(message) + "\n";
}

std::string format_error(const json& error) {
    return fmt::format("error {}: {}", get(error, "code", 0),
                       word(error, "message", "(no message)"));
}

}  // namespace gport::cli

namespace gport::cli {

std::string format_error(const client::Error& error) {
    if (error.code() == static_cast<int>(client::ErrorCode::kTransport) ||
        error.code() == static_cast<int>(client::ErrorCode::kTimeout) ||
        error.code() == static_cast<int>(client::ErrorCode::kBadReply)) {
        return printable(error.what());
    }
    return format_error(json{{"code", error.code()}, {"message", error.message()}});
}

json cli_wording(const json& error) {
    if (!error.is_object() || !error.contains("message") || !error["message"].is_string()) {
        return error;
    }
    static const std::regex kRecord(R"(send record \{"on": (true|false), "force": true\})");
    static const std::regex kClamp(R"(\bclamp: true\b)");
    auto message = error["message"].get<std::string>();
    std::smatch match;
    if (std::regex_search(message, match, kRecord)) {
        message = match.prefix().str() + "run 'gportctl record " +
                  (match[1] == "true" ? "on" : "off") + " --force'" + match.suffix().str();
    }
    message = std::regex_replace(message, kClamp, "--clamp");
    auto worded = error;
    worded["message"] = message;
    return worded;
}

std::string format_timestamp(std::chrono::system_clock::time_point when) {
    using namespace std::chrono;
    const auto seconds = system_clock::to_time_t(when);
    const auto ms = duration_cast<milliseconds>(when.time_since_epoch()).count() % 1000;
    std::tm local{};
    ::localtime_r(&seconds, &local);
    char date[32];
    char zone[8];
    std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%S", &local);
    std::strftime(zone, sizeof zone, "%z", &local);  // +0200
    const std::string offset(zone);
    return fmt::format("{}.{:03}{}:{}", date, ms < 0 ? ms + 1000 : ms, offset.substr(0, 3),
                       offset.substr(3, 2));
}

}  // namespace gport::cli
