#include "vehicle_text.hpp"

#include <fmt/format.h>

#include <optional>

#include "gport/cli/printable.hpp"
#include "gport/client/error.hpp"
#include "gport/client/results.hpp"

namespace gport::cli {
namespace {

using nlohmann::json;

std::optional<double> number(const json& object, const char* name) {
    const auto it = object.find(name);
    return it != object.end() && it->is_number() ? std::optional(it->get<double>()) : std::nullopt;
}

std::string position_text(const json& p) {
    const auto lat = number(p, "lat");
    const auto lon = number(p, "lon");
    if (!lat || !lon) {
        return "position unknown";
    }
    std::string out = fmt::format("{:.7f}, {:.7f}", *lat, *lon);
    if (const auto alt = number(p, "alt_msl_m")) {
        out += fmt::format(", {:.1f} m MSL", *alt);
    }
    if (const auto fix = number(p, "fix")) {
        out += fmt::format(", fix {:.0f}", *fix);
    }
    if (const auto acc = number(p, "h_acc_m")) {
        out += fmt::format(" (±{:.2f} m)", *acc);
    }
    return out;
}

std::string source_text(const json& source) {
    if (!source.is_object()) {
        return "no source connected";
    }
    return fmt::format("from pid {:.0f}", number(source, "pid").value_or(0));
}

}  // namespace

std::string vehicle_status_line(const json& status) {
    const auto it = status.find("vehicle");
    if (it == status.end() || !it->is_object()) {
        return "vehicle:   none (nothing publishes the vehicle's state; captures carry no "
               "vehicle)\n";
    }
    const json& v = *it;
    const auto position = v.find("position");
    std::string where = "no position";
    if (position != v.end() && position->is_object()) {
        where = position_text(*position);
        if (const auto age = number(v, "position_age_ms")) {
            where += fmt::format(", {:.0f} ms old", *age);
        }
    }
    const auto utc = v.find("utc_known");
    const bool utc_known = utc != v.end() && utc->is_boolean() && utc->get<bool>();
    return fmt::format("vehicle:   {}; {}; UTC {}; {:.0f} reports taken, {:.0f} refused\n", where,
                       source_text(v.value("source", json())),
                       utc_known ? "from the autopilot" : "unknown",
                       number(v, "published").value_or(0), number(v, "refused").value_or(0));
}

std::string capture_vehicle_suffix(const json& result) {
    const auto capture = result.find("capture");
    if (capture == result.end() || !capture->is_object()) {
        return "";
    }
    try {
        const auto stamp = client::capture_stamp_from_json(capture->dump());
        if (!stamp.vehicle) {
            return "";
        }
        const auto& v = *stamp.vehicle;
        if (!v.tagged) {
            return ", untagged: " + printable(v.why);
        }
        return fmt::format(", at {:.7f}, {:.7f}{}", v.lat, v.lon,
                           v.h_acc_m ? fmt::format(" (±{:.2f} m)", *v.h_acc_m) : std::string());
    } catch (const client::Error& e) {
        return ", vehicle unreadable: " + printable(e.message());
    }
}

}  // namespace gport::cli
