#include "capture_methods.hpp"

#include <fmt/format.h>

#include <chrono>
#include <fstream>
#include <string>

#include "json_common.hpp"
#include "params.hpp"
#include "vehicle_json.hpp"

namespace gport::ipc::detail {
namespace {

using capture::CaptureLog;
using nlohmann::json;

std::int64_t micros(std::chrono::nanoseconds since_epoch) {
    return std::chrono::duration_cast<std::chrono::microseconds>(since_epoch).count();
}

// The process's name from /proc (procfs: no disk involved); empty if gone.
std::string process_name(pid_t pid) {
    std::ifstream comm(fmt::format("/proc/{}/comm", pid));
    std::string name;
    std::getline(comm, name);
    return name;
}

// `meta`: absent, or an object of at most kMetaMaxBytes as compact JSON.
const json* checked_meta(const json& params) {
    if (!params.is_object()) {
        return nullptr;
    }
    const auto it = params.find("meta");
    if (it == params.end()) {
        return nullptr;
    }
    if (!it->is_object()) {
        throw InvalidParams(
            fmt::format("meta must be a JSON object (at most {} bytes as compact "
                        "JSON), not {}",
                        CaptureLog::kMetaMaxBytes, it->type_name()));
    }
    const auto size = json_text(*it).size();
    if (size > CaptureLog::kMetaMaxBytes) {
        throw InvalidParams(fmt::format("meta is {} bytes as compact JSON; at most {} are allowed",
                                        size, CaptureLog::kMetaMaxBytes));
    }
    return &*it;
}

// The capture built before its frame is sent: a request sends and records,
// or does neither. Empty (and answered -32603, naming why) when no index
// can be given now. `summary` is what the reply carries of it besides the
// index and kind: utc_us and the attitude logged with it.
struct Pending {
    CaptureLog::Prepared prepared;
    json summary;
};

std::optional<Pending> prepare(MethodContext& c, const json* meta, const Respond& respond) {
    const json capture = capture_json(c.client.info, c.api.latest_attitude(), meta);
    auto prepared = c.captures.prepare(capture);
    if (auto* why = std::get_if<std::string>(&prepared)) {
        respond(Reply::error(rpc_error::kInternal, std::move(*why)));
        return std::nullopt;
    }
    return Pending{std::get<CaptureLog::Prepared>(std::move(prepared)),
                   {{"utc_us", capture["utc_us"]}, {"attitude", capture["attitude"]}}};
}

// The frame went: when it is due on the line, the instant stamped (that plus
// camera.shutter_delay_ms) on the clock of mono_us, and the vehicle then.
void add_moment(Pending& pending, const daemon::CaptureMoment& moment) {
    pending.prepared.append("line_mono_us", micros(moment.on_wire.time_since_epoch()));
    pending.prepared.append("shutter_mono_us", micros(moment.instant.time_since_epoch()));
    auto vehicle = vehicle_stamp_json(moment.vehicle);
    pending.summary["vehicle"] = vehicle;
    pending.prepared.append("vehicle", vehicle);
}

// Gives the capture its index and returns the summary the reply carries:
// index, utc_us, kind, the attitude logged with it and the vehicle.
json take(MethodContext& c, Pending pending, std::string_view kind) {
    const auto stored = c.captures.add(std::move(pending.prepared), kind);
    json summary = std::move(pending.summary);
    summary["index"] = stored.index;
    summary["kind"] = kind;
    return summary;
}

std::string_view record_kind(daemon::RecordingState now) {
    switch (now) {
        case daemon::RecordingState::kOn:
            return "record_start";
        case daemon::RecordingState::kOff:
            return "record_stop";
        case daemon::RecordingState::kUnknown:
            break;
    }
    return "record_toggle";
}

}  // namespace

json capture_json(const daemon::ClientInfo& client,
                  const std::optional<daemon::AttitudeSample>& attitude, const json* meta) {
    const auto wall = std::chrono::system_clock::now();
    const auto mono = std::chrono::steady_clock::now();
    json out = {{"utc_us", micros(wall.time_since_epoch())},
                {"mono_us", micros(mono.time_since_epoch())}};
    if (attitude) {
        const auto age =
            std::chrono::duration_cast<std::chrono::milliseconds>(mono - attitude->received);
        out["attitude"] = {{"imu", axes_json(attitude->attitude.imu)},
                           {"hall", axes_json(attitude->attitude.hall)},
                           {"age_ms", age.count()}};
    } else {
        out["attitude"] = nullptr;
    }
    json who = {{"pid", client.pid}, {"uid", client.uid}};
    if (auto name = process_name(client.pid); !name.empty()) {
        who["name"] = std::move(name);
    }
    out["client"] = std::move(who);
    if (meta != nullptr) {
        out["meta"] = *meta;
    }
    return out;
}

void photo(MethodContext& c, const json& params, Respond respond) {
    Params(params).only({"meta"});
    auto prepared = prepare(c, checked_meta(params), respond);
    if (!prepared) {
        return;
    }
    auto outcome = c.api.photo(c.client.info);
    if (!outcome) {
        respond(Reply::error(outcome.error().code, outcome.error().message));
        return;
    }
    add_moment(*prepared, *outcome);
    respond(json{{"sent", true}, {"capture", take(c, std::move(*prepared), "photo")}});
}

void record(MethodContext& c, const json& params, Respond respond) {
    const Params p(params);
    p.only({"on", "force", "meta"});
    daemon::RecordRequest request;
    request.on = p.boolean("on");
    request.force = p.boolean("force").value_or(false);
    if (request.force && !request.on) {
        throw InvalidParams("force needs on: record {\"on\": true|false, \"force\": true}");
    }
    auto prepared = prepare(c, checked_meta(params), respond);
    if (!prepared) {
        return;
    }
    auto outcome = c.api.record(c.client.info, request);
    if (!outcome) {
        respond(Reply::error(outcome.error().code, outcome.error().message));
        return;
    }
    json result{{"sent", outcome->sent}, {"recording", daemon::to_string(outcome->recording)}};
    if (outcome->sent) {
        if (outcome->moment) {
            add_moment(*prepared, *outcome->moment);
        }
        result["capture"] = take(c, std::move(*prepared), record_kind(outcome->recording));
    }
    respond(std::move(result));
}

void captures(MethodContext& c, const json& params, Respond respond) {
    const Params p(params);
    p.only({"since", "limit"});
    const auto since = p.integer("since", 0, std::numeric_limits<std::int64_t>::max()).value_or(0);
    const auto limit = p.integer("limit", 1, static_cast<std::int64_t>(CaptureLog::kMaxLimit))
                           .value_or(static_cast<std::int64_t>(CaptureLog::kDefaultLimit));
    respond(Reply::raw(
        c.captures.list(static_cast<std::uint64_t>(since), static_cast<std::size_t>(limit))));
}

}  // namespace gport::ipc::detail
