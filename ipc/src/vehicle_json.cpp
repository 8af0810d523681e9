// publish_vehicle's parameters, and the vehicle as captures and status show
// it (docs/api.md, "The vehicle").
#include "vehicle_json.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "json_common.hpp"
#include "params.hpp"

namespace gport::ipc::detail {
namespace {

using nlohmann::json;

constexpr std::int64_t kMaxBootMs = std::numeric_limits<std::uint32_t>::max();

// A member's number rounded to `step` (the shortest text that reads back
// the same: 1e-8° is 1 mm; lengths to the millimetre).
json rounded(double value, double step) {
    return std::round(value / step) * step;
}

json velocity_json(const std::array<double, 3>& v) {
    return {rounded(v[0], 1e-3), rounded(v[1], 1e-3), rounded(v[2], 1e-3)};
}

json optional_rounded(const std::optional<double>& value, double step) {
    return value ? rounded(*value, step) : json(nullptr);
}

template <typename T>
json optional_value(const std::optional<T>& value) {
    return value ? json(*value) : json(nullptr);
}

// An object member `name` of `params`: null when absent; else its members,
// each named "name.member" in an error.
const json* part(const json& params, const char* name) {
    const auto it = params.find(name);
    if (it == params.end() || it->is_null()) {
        return nullptr;
    }
    if (!it->is_object()) {
        throw InvalidParams(fmt::format("{} must be an object, got {}", name, it->type_name()));
    }
    return &*it;
}

template <typename Read>
auto prefixed(const char* name, Read&& read) {
    try {
        return read();
    } catch (const InvalidParams& e) {
        // "position.lat must be ..."; "position: unknown parameter ..."
        const std::string_view what = e.what();
        const bool member_first = !what.starts_with("unknown") && !what.starts_with("params");
        throw InvalidParams(fmt::format("{}{}{}", name, member_first ? "." : ": ", what));
    }
}

double required(const Params& p, std::string_view name) {
    auto value = p.number(name);
    if (!value) {
        throw InvalidParams(fmt::format("{} is required", name));
    }
    return *value;
}

std::uint32_t boot_ms(const Params& p) {
    auto value = p.integer("boot_ms", 0, kMaxBootMs);
    if (!value) {
        throw InvalidParams(
            fmt::format("boot_ms is required: the autopilot's boot time of the sample, 0 to {} ms",
                        kMaxBootMs));
    }
    return static_cast<std::uint32_t>(*value);
}

std::array<double, 3> velocity(const json& position) {
    const auto it = position.find("velocity_ned");
    if (it == position.end() || !it->is_array() || it->size() != 3 ||
        !std::all_of(it->begin(), it->end(), [](const json& v) { return v.is_number(); })) {
        throw InvalidParams("velocity_ned is required: [north, east, down] in m/s");
    }
    return {(*it)[0].get<double>(), (*it)[1].get<double>(), (*it)[2].get<double>()};
}

daemon::VehiclePosition read_position(const json& position) {
    const Params p(position);
    p.only({"boot_ms", "lat", "lon", "alt_msl_m", "alt_rel_m", "velocity_ned", "heading_deg",
            "yaw_rate_dps", "fix", "h_acc_m", "v_acc_m", "satellites"});
    daemon::VehiclePosition out;
    out.boot_ms = boot_ms(p);
    out.lat_deg = required(p, "lat");
    out.lon_deg = required(p, "lon");
    out.alt_msl_m = required(p, "alt_msl_m");
    out.alt_rel_m = p.number("alt_rel_m");
    out.velocity_ned = velocity(position);
    out.heading_deg = p.number("heading_deg");
    out.yaw_rate_dps = p.number("yaw_rate_dps");
    if (auto fix = p.integer("fix", 0, 8)) {
        out.fix = static_cast<int>(*fix);
    }
    out.h_acc_m = p.number("h_acc_m");
    out.v_acc_m = p.number("v_acc_m");
    if (auto n = p.integer("satellites", 0, 255)) {
        out.satellites = static_cast<int>(*n);
    }
    return out;
}

daemon::VehicleTime read_time(const json& time) {
    const Params p(time);
    p.only({"boot_ms", "utc_us"});
    daemon::VehicleTime out;
    out.boot_ms = boot_ms(p);
    auto utc = p.integer("utc_us", 0, std::numeric_limits<std::int64_t>::max());
    if (!utc) {
        throw InvalidParams("utc_us is required: SYSTEM_TIME's time_unix_usec");
    }
    out.utc_us = *utc;
    return out;
}

json position_json(const daemon::VehiclePosition& p) {
    return {{"boot_ms", p.boot_ms},
            {"lat", rounded(p.lat_deg, 1e-8)},
            {"lon", rounded(p.lon_deg, 1e-8)},
            {"alt_msl_m", rounded(p.alt_msl_m, 1e-3)},
            {"alt_rel_m", optional_rounded(p.alt_rel_m, 1e-3)},
            {"velocity_ned", velocity_json(p.velocity_ned)},
            {"heading_deg", optional_rounded(p.heading_deg, 1e-2)},
            {"fix", optional_value(p.fix)},
            {"h_acc_m", optional_rounded(p.h_acc_m, 1e-3)},
            {"v_acc_m", optional_rounded(p.v_acc_m, 1e-3)},
            {"satellites", optional_value(p.satellites)}};
}

json millis_or_null(const std::optional<daemon::Millis>& value) {
    return value ? json(value->count()) : json(nullptr);
}

}  // namespace

daemon::VehicleReport vehicle_report(const json& params) {
    Params(params).only({"position", "time"});
    daemon::VehicleReport report;
    if (const json* position = params.is_object() ? part(params, "position") : nullptr) {
        report.position = prefixed("position", [&] { return read_position(*position); });
    }
    if (const json* time = params.is_object() ? part(params, "time") : nullptr) {
        report.time = prefixed("time", [&] { return read_time(*time); });
    }
    return report;
}

void publish_vehicle(MethodContext& c, const json& params, Respond respond) {
    const auto report = vehicle_report(params);
    auto outcome = c.api.publish_vehicle(c.client.info, report);
    if (!outcome) {
        respond(Reply::error(outcome.error().code, outcome.error().message));
        return;
    }
    respond(json{{"taken", true}});
}

json vehicle_stamp_json(const std::optional<daemon::VehicleStamp>& stamp) {
    if (!stamp) {
        return nullptr;
    }
    const auto& s = *stamp;
    json out = {{"tagged", s.tagged}, {"utc_us", optional_value(s.utc_us)}};
    if (!s.tagged) {
        out["why"] = s.why;
        return out;
    }
    out.update(json{{"lat", rounded(s.lat_deg, 1e-8)},
                    {"lon", rounded(s.lon_deg, 1e-8)},
                    {"alt_msl_m", rounded(s.alt_msl_m, 1e-3)},
                    {"alt_rel_m", optional_rounded(s.alt_rel_m, 1e-3)},
                    {"velocity_ned", velocity_json(s.velocity_ned)},
                    {"heading_deg", optional_rounded(s.heading_deg, 1e-2)},
                    {"h_acc_m", optional_rounded(s.h_acc_m, 1e-3)},
                    {"v_acc_m", optional_rounded(s.v_acc_m, 1e-3)},
                    {"fix", optional_value(s.fix)},
                    {"satellites", optional_value(s.satellites)},
                    {"age_ms", s.age.count()}});
    return out;
}

json vehicle_status_json(const std::optional<daemon::VehicleStatus>& status) {
    if (!status) {
        return nullptr;
    }
    const auto& s = *status;
    return {{"source", s.source ? client_json(*s.source) : json(nullptr)},
            {"position", s.position ? position_json(*s.position) : json(nullptr)},
            {"position_age_ms", millis_or_null(s.position_age)},
            {"utc_known", s.utc_known},
            {"time_age_ms", millis_or_null(s.time_age)},
            {"published", s.published},
            {"refused", s.refused},
            {"resets", s.resets}};
}

}  // namespace gport::ipc::detail
