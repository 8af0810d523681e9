#include "result_json.hpp"

#include "gport/contract/counters.hpp"
#include "gport/contract/names.hpp"
#include "gport/version.hpp"
#include "json_common.hpp"
#include "vehicle_json.hpp"

namespace gport::ipc::detail {

namespace {

using nlohmann::json;

// Bumped when a method, field or notification changes incompatibly.
constexpr int kApiVersion = 1;

// The contract's field list, in its order (gport/contract/counters.hpp).
json counters_json(const daemon::Counters& c, std::uint64_t dropped) {
    json out = json::object();
#define GPORT_IPC_COUNTER(name) out[#name] = c.name;
    GPORT_CONTRACT_CORE_COUNTERS(GPORT_IPC_COUNTER)
#undef GPORT_IPC_COUNTER
    out["dropped_notifications"] = dropped;
    return out;
}

json motion_json(const std::optional<daemon::MotionStatus>& motion) {
    if (!motion) {
        return nullptr;
    }
    json out = {{"mode", daemon::to_string(motion->mode)},
                {"owner", motion->owner ? client_json(*motion->owner) : json(nullptr)}};
    if (motion->mode == daemon::MotionMode::kSpeed) {
        out["speed"] = axes_json(motion->speed);
        out["time_left_ms"] = motion->time_left.count();
    } else {  // a tracked angle or centre motion
        out["target"] = axes_json(motion->target);
    }
    out["elapsed_ms"] = motion->elapsed.count();
    return out;
}

json optional_client(const std::optional<daemon::ClientInfo>& client) {
    return client ? client_json(*client) : json(nullptr);
}

}  // namespace

json client_status_json(const ClientState& client) {
    json you = client_json(client.info);
    you["dropped"] = client.dropped;
    you["attitude_channel"] = client.attitude_channel;
    return you;
}

json shared_status_json(const daemon::Status& status, const ServerStats& stats) {
    return {{"api_version", kApiVersion},
            {"daemon_version", kVersion},
            {"link", {{"state", daemon::to_string(status.link)}, {"reason", status.link_reason}}},
            {"device", status.device},
            {"device_open", status.device_open},
            {"device_error", status.device_error ? json(*status.device_error) : json(nullptr)},
            {"uptime_ms", status.uptime.count()},
            {"attitude_age_ms",
             status.attitude_age ? json(status.attitude_age->count()) : json(nullptr)},
            {"counters", counters_json(status.counters, stats.dropped_notifications)},
            {"clients", stats.clients},
            {"attitude_channel_clients", stats.attitude_channel_clients},
            {"attitude_channel_failures", stats.attitude_channel_failures},
            {"dropped_notifications", stats.dropped_notifications},
            {"motion", motion_json(status.motion)},
            {"controller", optional_client(status.controller)},
            {"recording", daemon::to_string(status.recording)},
            {"camera",
             {{"max_commands_per_s", status.camera.max_commands_per_s},
              {"refused", status.camera.refused}}},
            {"vehicle", vehicle_status_json(status.vehicle)},
            {"config_file", stats.config_file ? json(*stats.config_file) : json(nullptr)},
            {"loop",
             {{"worst_request_us", stats.worst_request_us},
              {"worst_method",
               stats.worst_method.empty() ? json(nullptr) : json(stats.worst_method)}}}};
}

json controller_json(const std::optional<daemon::ClientInfo>& holder,
                     const daemon::ClientInfo& caller) {
    return {{"controller", optional_client(holder)},
            {"you_hold_control", holder && holder->id == caller.id}};
}

json settings_json(const daemon::Settings& settings) {
    return {{"dead_zone", settings.dead_zone},
            {"follow_speed", settings.follow_speed},
            {"inverted", settings.inverted}};
}

json subscriptions_json(const Subscriptions& subscriptions) {
    json topics = json::array();
    if (subscriptions.attitude) {
        topics.push_back(std::string(contract::kTopicAttitude));
    }
    if (subscriptions.link) {
        topics.push_back(std::string(contract::kTopicLink));
    }
    if (subscriptions.motion) {
        topics.push_back(std::string(contract::kTopicMotion));
    }
    if (subscriptions.capture) {
        topics.push_back(std::string(contract::kTopicCapture));
    }
    json result = {{"topics", std::move(topics)}};
    result["max_rate_hz"] =
        subscriptions.max_rate_hz ? json(*subscriptions.max_rate_hz) : json(nullptr);
    return result;
}

}  // namespace gport::ipc::detail
