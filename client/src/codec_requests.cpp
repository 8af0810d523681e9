// Request params and reply errors (codec.hpp).
#include "codec.hpp"

namespace gport::client::codec {
namespace {

json axes_json(const Axes& a) {
    return {{"roll", a.roll}, {"pitch", a.pitch}, {"yaw", a.yaw}};
}

}  // namespace

json speed_params(const Axes& speed, const SpeedOptions& options) {
    json params = axes_json(speed);
    if (options.duration) {
        params["duration_ms"] = options.duration->count();
    }
    if (options.lease) {
        params["lease_ms"] = options.lease->count();
    }
    if (options.clamp) {
        params["clamp"] = true;
    }
    return params;
}

// `clamp` and `wait` are sent only when true, so that a daemon older than
// the option still takes the call.
json angle_params(const Axes& target, const AngleOptions& options) {
    json params = axes_json(target);
    if (options.clamp) {
        params["clamp"] = true;
    }
    if (options.wait) {
        params["wait"] = true;
    }
    return params;
}

json center_params(const CenterOptions& options) {
    json params = json::object();
    if (options.wait) {
        params["wait"] = true;
    }
    return params;
}

json record_params(std::optional<bool> on, bool force) {
    json params = json::object();
    if (on) {
        params["on"] = *on;
        if (force) {
            params["force"] = true;
        }
    }
    return params;
}

namespace {

template <typename T>
void put(json& object, const char* name, const std::optional<T>& value) {
    if (value) {
        object[name] = *value;
    }
}

}  // namespace

json vehicle_params(const VehicleReport& report) {
    json params = json::object();
    if (const auto& p = report.position) {
        json position = {{"boot_ms", p->boot_ms},
                         {"lat", p->lat},
                         {"lon", p->lon},
                         {"alt_msl_m", p->alt_msl_m},
                         {"velocity_ned", p->velocity_ned}};
        put(position, "alt_rel_m", p->alt_rel_m);
        put(position, "heading_deg", p->heading_deg);
        put(position, "yaw_rate_dps", p->yaw_rate_dps);
        put(position, "fix", p->fix);
        put(position, "h_acc_m", p->h_acc_m);
        put(position, "v_acc_m", p->v_acc_m);
        put(position, "satellites", p->satellites);
        params["position"] = std::move(position);
    }
    if (const auto& t = report.time) {
        params["time"] = {{"boot_ms", t->boot_ms}, {"utc_us", t->utc_us}};
    }
    return params;
}

std::optional<Error> add_meta(json& params, const CaptureOptions& options) {
    if (options.meta.empty()) {
        return std::nullopt;
    }
    json meta = json::parse(options.meta, nullptr, false);
    if (!meta.is_object()) {
        return Error(ErrorCode::kInvalidParams,
                     "meta: \"" + options.meta.substr(0, 40) +
                         "\" is not the text of a JSON object; meta must be one");
    }
    params["meta"] = std::move(meta);
    return std::nullopt;
}

json settings_params(const SettingsChange& change) {
    json params = json::object();
    if (change.dead_zone) {
        params["dead_zone"] = *change.dead_zone;
    }
    if (change.follow_speed) {
        params["follow_speed"] = *change.follow_speed;
    }
    if (change.inverted) {
        params["inverted"] = *change.inverted;
    }
    return params;
}

json subscribe_params(const std::vector<std::string>& topics, std::optional<double> max_rate_hz) {
    json params = {{"topics", topics}};
    if (max_rate_hz) {
        params["max_rate_hz"] = *max_rate_hz;
    }
    return params;
}

json unsubscribe_params(const std::vector<std::string>& topics) {
    json params = json::object();
    if (!topics.empty()) {
        params["topics"] = topics;
    }
    return params;
}

json result_of(const json& reply) {
    if (!reply.is_object()) {
        throw Error(ErrorCode::kBadReply, "a reply that is not a JSON object: " + reply.dump());
    }
    if (const auto error = reply.find("error"); error != reply.end()) {
        if (!error->is_object() || !error->contains("code") || !(*error)["code"].is_number()) {
            throw Error(ErrorCode::kBadReply, "an error without a code: " + error->dump());
        }
        const auto message = error->value("message", std::string());
        throw Error((*error)["code"].get<int>(), message);
    }
    if (const auto result = reply.find("result"); result != reply.end()) {
        return *result;
    }
    throw Error(ErrorCode::kBadReply, "a reply with neither result nor error: " + reply.dump());
}

std::optional<std::chrono::milliseconds> reply_limit(
    const json& params, std::optional<std::chrono::milliseconds> call_timeout) {
    if (!call_timeout) {
        return std::nullopt;
    }
    const bool wait = params.is_object() && params.value("wait", json(false)) == json(true);
    return wait ? *call_timeout + kWaitAllowance : *call_timeout;
}

Error no_reply(const std::string& method, std::chrono::milliseconds limit) {
    return Error(ErrorCode::kTimeout, "no reply to " + method + " within " +
                                          std::to_string(limit.count()) +
                                          " ms (the client's call timeout); gportd may still "
                                          "carry the request out");
}

}  // namespace gport::client::codec
