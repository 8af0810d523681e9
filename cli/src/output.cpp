#include "gport/cli/output.hpp"

#include <fmt/format.h>
#include <time.h>

#include <regex>

#include "gport/cli/printable.hpp"
#include "gport/client/results.hpp"
#include "gport/contract/limits.hpp"
#include "vehicle_text.hpp"

namespace gport::cli {
namespace {

using nlohmann::json;

// gportd's words and a peer's text, safe for the terminal; `fallback` when
// there are none.
std::string text(const std::string& value, const char* fallback = "?") {
    return printable(value.empty() ? fallback : value);
}

std::string axes(const client::Axes& a) {
    return fmt::format("roll {:.2f} pitch {:.2f} yaw {:.2f}", a.roll, a.pitch, a.yaw);
}

std::string client_text(const std::optional<client::Peer>& c) {
    if (!c) {
        return "nobody";
    }
    return fmt::format("pid {} (uid {}, client {})", c->pid, c->uid, c->id);
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

std::string attitude(const client::AttitudeSample& a) {
    std::string out = fmt::format("seq {}  imu {}  hall {}", a.seq, axes(a.imu), axes(a.hall));
    if (a.rates) {
        const auto& imu = a.rates->imu;
        out += fmt::format("  rates hall {}  imu x {:.2f} y {:.2f} z {:.2f}", axes(a.rates->hall),
                           imu.x, imu.y, imu.z);
    }
    if (a.dropped > 0) {  // gportd sends it once the client has lost samples
        out += fmt::format("  ({} dropped so far)", a.dropped);
    }
    return out;
}

std::string motion(const std::optional<client::Motion>& m) {
    if (!m) {
        return "none";
    }
    if (m->target) {  // a tracked angle or centre motion
        return fmt::format("{} to {} deg, {} ms so far, owner {}", text(m->mode), axes(*m->target),
                           m->elapsed_ms.value_or(0), client_text(m->owner));
    }
    return fmt::format("{} {} deg/s, {} ms left, owner {}", text(m->mode),
                       axes(m->speed.value_or(client::Axes{})), m->time_left_ms.value_or(0),
                       client_text(m->owner));
}

std::string status(const client::Status& s) {
    const auto& c = s.counters;
    std::string out;
    out += fmt::format("link:      {} ({})\n", text(s.link.state), text(s.link.reason, ""));
    const auto error = text(s.device_error.value_or(""), "");
    out += fmt::format("device:    {} ({})\n", text(s.device),
                       s.device_open   ? "open"
                       : error.empty() ? "closed"
                                       : "closed: " + error);
    out += fmt::format("daemon:    gportd {}, API {}, up {}\n", text(s.daemon_version),
                       s.api_version, duration(s.uptime_ms));
    out += fmt::format("attitude:  {}\n", s.attitude_age_ms
                                              ? fmt::format("{} ms old", *s.attitude_age_ms)
                                              : std::string("none received"));
    out += fmt::format("clients:   {}\n", s.clients);
    out += fmt::format("motion:    {}\n", motion(s.motion));
    out += fmt::format("control:   {}\n", s.controller ? "held by " + client_text(s.controller)
                                                       : std::string("free (last command wins)"));
    out += fmt::format("recording: {} (assumed)\n", text(s.recording, "unknown"));
    out += fmt::format("frames:    in {} ({} bytes), out {} ({} bytes), attitude {}\n", c.frames_in,
                       c.bytes_in, c.frames_out, c.bytes_out, c.attitude_frames);
    out += fmt::format("errors:    crc {}, header {}, resyncs {}, garbage bytes {}\n", c.crc_errors,
                       c.header_errors, c.resyncs, c.garbage_bytes);
    out += fmt::format("dropped:   {} notifications in total\n", s.dropped_notifications);
    return out;
}

// angle and center: "sent", what was clamped, and with --wait how it ended.
// center's result has the shape of angle's (sent, clamped, ended), its
// target named `target`: only angle's is printed, as the user typed it.
std::string position(const std::string& command, const client::AngleResult& result) {
    std::string out = fmt::format("{}: sent", command);
    if (command == "angle") {
        out += " " + axes(result.angle) + " deg";
    }
    std::string clamped;
    for (const auto& axis : result.clamped) {
        clamped += (clamped.empty() ? "" : ", ") + printable(axis);
    }
    if (!clamped.empty()) {
        out += " (clamped: " + clamped + ")";
    }
    out += "\n";
    if (const auto& ended = result.ended) {
        out += fmt::format("ended: {} after {} ms; {}\n", text(ended->reason), ended->elapsed_ms,
                           ended->attitude ? "hall " + axes(ended->attitude->hall)
                                           : std::string("no attitude received"));
        if (!ended->detail.empty()) {  // stalled: where the gimbal stopped
            out += printable(ended->detail) + "\n";
        }
    }
    return out;
}

std::string settings(const client::Settings& s) {
    return fmt::format("dead zone:     {}\nfollow speed:  {}\ninverted:      {}\n", s.dead_zone,
                       s.follow_speed, s.inverted ? "yes" : "no");
}

// limits: one line per axis, then speed and margin; "no limit" for the
// protocol's whole range.
std::string limits(const client::Limits& l) {
    using contract::kMaxDegrees;
    std::string out;
    for (const auto& [axis, range] :
         {std::pair{"roll", l.roll}, std::pair{"pitch", l.pitch}, std::pair{"yaw", l.yaw}}) {
        out +=
            fmt::format("{:<16}{} to {} deg{}\n", std::string(axis) + ":", range.min, range.max,
                        range.min <= -kMaxDegrees && range.max >= kMaxDegrees ? " (no limit)" : "");
    }
    out += fmt::format("{:<16}{} deg/s{}\n", "max speed:", l.max_speed,
                       l.max_speed >= kMaxDegrees ? " (no limit)" : "");
    out += fmt::format("{:<16}{} deg\n", "braking margin:", l.braking_margin_deg);
    return out;
}

// ", capture 12" when gportd logged the capture.
std::string capture_suffix(const std::optional<client::Capture>& capture) {
    return capture ? fmt::format(", capture {}", capture->index) : "";
}

std::string topics(const std::vector<std::string>& watched) {
    std::string out;
    for (const auto& t : watched) {
        out += (out.empty() ? "" : ", ") + printable(t);
    }
    return out.empty() ? "nothing" : out;
}

std::string notification(const client::Notification& n) {
    if (const auto* a = std::get_if<client::AttitudeSample>(&n)) {
        return "attitude  " + attitude(*a) + "\n";
    }
    if (const auto* l = std::get_if<client::LinkEvent>(&n)) {
        return fmt::format("link      {} ({})\n", text(l->state), text(l->reason, ""));
    }
    const auto& m = std::get<client::MotionEvent>(n);
    std::string out = fmt::format("motion    {} {}", text(m.change), text(m.mode));
    if (m.speed) {
        out += " " + axes(*m.speed) + " deg/s";
    }
    if (m.target) {
        out += " to " + axes(*m.target) + " deg";
    }
    if (m.reason) {
        out += ", reason " + text(*m.reason);
    }
    return out + ", owner " + client_text(m.owner) + "\n";
}

}  // namespace

std::string format_result(const std::string& command, const json& result) {
    const auto r = result.dump();
    if (command == "status") {
        return status(client::status_from_json(r)) + vehicle_status_line(result);
    }
    if (command == "attitude") {
        const auto a = client::attitude_from_json(r);
        return attitude(a) + fmt::format("  (age {} ms)\n", a.age_ms.value_or(0));
    }
    if (command == "settings") {
        return settings(client::settings_from_json(r));
    }
    if (command == "limits") {
        return limits(client::limits_from_json(r));
    }
    if (command == "angle" || command == "center") {
        return position(command, client::angle_result_from_json(r));
    }
    if (command == "speed") {
        return fmt::format("moving for {} ms\n", client::speed_result_from_json(r).duration_ms);
    }
    if (command == "watch") {
        return fmt::format("watching {} (Ctrl-C to stop)\n",
                           topics(client::subscription_from_json(r).topics));
    }
    if (command == "record" && result.contains("recording")) {
        const auto record = client::record_result_from_json(r);
        return fmt::format("record: {}{}{}; recording {} (assumed)\n",
                           record.sent ? "sent" : "nothing sent", capture_suffix(record.capture),
                           capture_vehicle_suffix(result), text(record.recording, "unknown"));
    }
    if (command == "photo") {
        return fmt::format("photo: sent{}{}\n",
                           capture_suffix(client::photo_result_from_json(r).capture),
                           capture_vehicle_suffix(result));
    }
    return fmt::format("{}: sent\n", command);
}

std::string format_notification(const json& message) {
    try {
        if (const auto n = client::notification_from_json(message.dump())) {
            return notification(*n);
        }
    } catch (const client::Error&) {
        // A shape the library cannot read is shown as it came, like a topic
        // it does not know: the watch goes on.
    }
    return json_line(message) + "\n";
}

std::string format_error(const json& error) {
    const auto code = error.is_object() ? error.value("code", json()) : json();
    const auto message = error.is_object() ? error.value("message", json()) : json();
    return fmt::format(
        "error {}: {}", code.is_number_integer() ? code.get<long long>() : 0,
        message.is_string() ? printable(message.get<std::string>()) : std::string("(no message)"));
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
