// Typed results and notifications from gportd's JSON (codec.hpp), and the
// one way back: an attitude sample as gportd's notification
// (attitude_feed.hpp).
#include <utility>

#include "attitude_feed.hpp"
#include "codec.hpp"
#include "gport/contract/attitude_text.hpp"

namespace gport::client::codec {
namespace {

// Runs a decoder, turning nlohmann's type errors into Error (kBadReply).
template <typename F>
auto guarded(const char* what, const json& value, F&& decode) {
    if (!value.is_object()) {
        throw Error(ErrorCode::kBadReply,
                    std::string("a ") + what + " that is not an object: " + value.dump());
    }
    try {
        return std::forward<F>(decode)();
    } catch (const json::exception& e) {
        throw Error(ErrorCode::kBadReply,
                    std::string("cannot read a ") + what + " (" + e.what() + "): " + value.dump());
    }
}

template <typename T>
std::optional<T> optional_of(const json& object, const char* key) {
    const auto it = object.find(key);
    if (it == object.end() || it->is_null()) {
        return std::nullopt;
    }
    return it->get<T>();
}

Axes axes(const json& j) {
    return {j.value("roll", 0.0), j.value("pitch", 0.0), j.value("yaw", 0.0)};
}

std::optional<Axes> optional_axes(const json& object, const char* key) {
    const auto it = object.find(key);
    if (it == object.end() || !it->is_object()) {
        return std::nullopt;
    }
    return axes(*it);
}

// A motion's target: `target`, or `angle` from a daemon that sends only that.
std::optional<Axes> target_of(const json& object) {
    auto target = optional_axes(object, "target");
    return target ? target : optional_axes(object, "angle");
}

std::optional<Peer> peer(const json& object, const char* key) {
    const auto it = object.find(key);
    if (it == object.end() || !it->is_object()) {
        return std::nullopt;
    }
    return Peer{it->value("id", std::int64_t{0}), it->value("pid", std::int64_t{0}),
                it->value("uid", std::int64_t{0}), it->value("gid", std::int64_t{0})};
}

std::vector<std::string> strings(const json& object, const char* key) {
    return object.value(key, std::vector<std::string>{});
}

AttitudeSample sample(const json& j) {
    AttitudeSample s;
    s.seq = j.at("seq").get<std::uint64_t>();
    s.time = j.at("t").get<double>();
    s.imu = axes(j.at("imu"));
    s.hall = axes(j.at("hall"));
    if (const auto rates = j.find("rates"); rates != j.end() && rates->is_object()) {
        const auto& imu = rates->at("imu");
        s.rates = Rates{axes(rates->at("hall")),
                        {imu.value("x", 0.0), imu.value("y", 0.0), imu.value("z", 0.0)}};
    }
    s.age_ms = optional_of<std::int64_t>(j, "age_ms");
    s.dropped = j.value("dropped", std::uint64_t{0});
    return s;
}

std::optional<MotionEnd> motion_end(const json& result) {
    const auto it = result.find("ended");
    if (it == result.end() || !it->is_object()) {
        return std::nullopt;
    }
    MotionEnd end;
    end.reason = it->at("reason").get<std::string>();
    if (const auto a = it->find("attitude"); a != it->end() && a->is_object()) {
        end.attitude = sample(*a);
    }
    end.elapsed_ms = it->value("elapsed_ms", std::int64_t{0});
    if (const auto d = it->find("detail"); d != it->end() && d->is_string()) {
        end.detail = d->get<std::string>();
    }
    return end;
}

Counters counters(const json& j) {
    Counters c;
#define GPORT_CLIENT_COUNTER(name) c.name = j.value(#name, std::uint64_t{0});
    GPORT_CONTRACT_COUNTERS(GPORT_CLIENT_COUNTER)
#undef GPORT_CLIENT_COUNTER
    return c;
}

std::optional<Motion> motion(const json& status) {
    const auto it = status.find("motion");
    if (it == status.end() || !it->is_object()) {
        return std::nullopt;
    }
    const json& m = *it;
    Motion motion;
    motion.mode = m.value("mode", std::string());
    motion.owner = peer(m, "owner");
    motion.speed = optional_axes(m, "speed");
    motion.target = target_of(m);
    motion.time_left_ms = optional_of<std::int64_t>(m, "time_left_ms");
    motion.elapsed_ms = optional_of<std::int64_t>(m, "elapsed_ms");
    return motion;
}

}  // namespace

Status status(const json& result) {
    return guarded("status", result, [&] {
        Status s;
        s.api_version = result.value("api_version", 0);
        s.daemon_version = result.value("daemon_version", std::string());
        const auto& link = result.at("link");
        s.link = {link.value("state", std::string()), link.value("reason", std::string())};
        s.device = result.value("device", std::string());
        s.device_open = result.value("device_open", false);
        s.device_error = optional_of<std::string>(result, "device_error");
        s.uptime_ms = result.value("uptime_ms", std::int64_t{0});
        s.attitude_age_ms = optional_of<std::int64_t>(result, "attitude_age_ms");
        s.counters = counters(result.value("counters", json::object()));
        s.clients = result.value("clients", std::int64_t{0});
        s.dropped_notifications = result.value("dropped_notifications", std::uint64_t{0});
        s.motion = motion(result);
        s.controller = peer(result, "controller");
        s.recording = result.value("recording", std::string("unknown"));
        s.self = peer(result, "client").value_or(Peer{});
        s.self_dropped = result.value("client", json::object()).value("dropped", std::uint64_t{0});
        return s;
    });
}

AttitudeSample attitude(const json& result) {
    return guarded("attitude sample", result, [&] { return sample(result); });
}

SpeedResult speed_result(const json& result) {
    return guarded("speed result", result, [&] {
        return SpeedResult{result.value("duration_ms", std::int64_t{0}),
                           result.value("ends_at", 0.0), axes(result.at("speed")),
                           strings(result, "clamped")};
    });
}

AngleResult angle_result(const json& result) {
    return guarded("angle result", result, [&] {
        return AngleResult{result.value("sent", false), axes(result.value("angle", json::object())),
                           strings(result, "clamped"), motion_end(result)};
    });
}

CenterResult center_result(const json& result) {
    return guarded("center result", result, [&] {
        return CenterResult{result.value("sent", false), motion_end(result)};
    });
}

namespace {

std::optional<Capture> capture_of(const json& result) {
    if (!result.is_object() || !result.contains("capture") || result.at("capture").is_null()) {
        return std::nullopt;
    }
    const json& c = result.at("capture");
    Capture capture;
    capture.index = c.at("index").get<std::uint64_t>();
    if (c.contains("utc_us") && !c.at("utc_us").is_null()) {
        capture.utc_us = c.at("utc_us").get<std::uint64_t>();
    }
    capture.kind = c.value("kind", std::string());
    return capture;
}

// capture.attitude: {"imu":{...},"hall":{...},"age_ms":n} or null/absent.
std::optional<CaptureAttitude> capture_attitude_of(const json& result) {
    if (!result.is_object() || !result.contains("capture") || !result.at("capture").is_object()) {
        return std::nullopt;
    }
    const json& c = result.at("capture");
    const auto it = c.find("attitude");
    if (it == c.end() || !it->is_object()) {
        return std::nullopt;
    }
    return CaptureAttitude{axes(it->at("imu")), axes(it->at("hall")),
                           it->value("age_ms", std::int64_t{0})};
}

}  // namespace

RecordResult record_result(const json& result) {
    return guarded("record result", result, [&] {
        return RecordResult{result.at("sent").get<bool>(),
                            result.value("recording", std::string("unknown")), capture_of(result)};
    });
}

PhotoResult photo_result(const json& result) {
    return guarded("photo result", result, [&] { return PhotoResult{capture_of(result)}; });
}

PhotoReport photo_report(const json& result) {
    return guarded("photo result", result, [&] {
        return PhotoReport{capture_of(result), capture_attitude_of(result)};
    });
}

Control control(const json& result) {
    return guarded("control result", result, [&] {
        return Control{peer(result, "controller"), result.value("you_hold_control", false)};
    });
}

Settings settings(const json& result) {
    return guarded("settings result", result, [&] {
        return Settings{result.at("dead_zone").get<int>(), result.at("follow_speed").get<int>(),
                        result.at("inverted").get<bool>()};
    });
}

Limits limits(const json& result) {
    return guarded("limits result", result, [&] {
        const auto range = [&](const char* axis) {
            const json& r = result.at(axis);
            return AxisRange{r.at("min").get<double>(), r.at("max").get<double>()};
        };
        return Limits{range("roll"), range("pitch"), range("yaw"),
                      result.at("max_speed").get<double>(),
                      result.at("braking_margin_deg").get<double>()};
    });
}

Subscription subscription(const json& result) {
    return guarded("subscription", result, [&] {
        return Subscription{strings(result, "topics"), optional_of<double>(result, "max_rate_hz")};
    });
}

std::optional<Notification> notification(const json& message) {
    const auto method = message.value("method", std::string());
    const auto& params = message.contains("params") ? message["params"] : json::object();
    if (method == "attitude") {
        return guarded("attitude notification", params, [&] { return sample(params); });
    }
    if (method == "link") {
        return guarded("link notification", params, [&] {
            return LinkEvent{params.value("state", std::string()),
                             params.value("reason", std::string())};
        });
    }
    if (method == "motion") {
        return guarded("motion notification", params, [&] {
            MotionEvent e;
            e.change = params.value("change", std::string());
            e.mode = params.value("mode", std::string());
            e.owner = peer(params, "owner");
            e.speed = optional_axes(params, "speed");
            e.target = target_of(params);
            e.duration_ms = optional_of<std::int64_t>(params, "duration_ms");
            e.reason = optional_of<std::string>(params, "reason");
            e.braked = strings(params, "braked");
            return e;
        });
    }
    return std::nullopt;
}

}  // namespace gport::client::codec

namespace gport::client {
namespace {

using nlohmann::json;

contract::AttitudePayload::Axes payload_axes(const Axes& a) {
    return {a.roll, a.pitch, a.yaw};
}

}  // namespace

json attitude_notification(const AttitudeSample& sample) {
    // gportd's own text (gport/contract/attitude_text.hpp) read back, so a
    // whole value is an integer as in what gportd sent.
    contract::AttitudePayload payload;
    payload.seq = sample.seq;
    payload.imu = payload_axes(sample.imu);
    payload.hall = payload_axes(sample.hall);
    if (sample.rates) {
        payload.rates =
            contract::AttitudePayload::Rates{payload_axes(sample.rates->hall), sample.rates->imu.x,
                                             sample.rates->imu.y, sample.rates->imu.z};
    }
    payload.dropped = sample.dropped;
    json params = json::parse(contract::attitude_payload_text(payload));
    // "t" is held as a double (gportd's six decimals read back), whatever a
    // server sent: given back as that double, never re-rounded.
    params["t"] = sample.time;
    return {{"jsonrpc", "2.0"}, {"method", "attitude"}, {"params", std::move(params)}};
}

}  // namespace gport::client
