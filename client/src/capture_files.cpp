// The capture log as CSV and GeoJSON (capture_files.hpp): one writer for
// gportctl and gport-web.
#include "gport/client/capture_files.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>

#include "gport/base/civil_time.hpp"
#include "gport/client/printable.hpp"

namespace gport::client {
namespace {

using nlohmann::json;

json parsed(std::string_view capture) {
    auto value = json::parse(capture, nullptr, false);
    if (value.is_discarded()) {
        throw Error(ErrorCode::kBadReply, "capture: not JSON: " + printable(capture.substr(0, 64)));
    }
    return value;
}

const json& member(const json& object, const char* key) {
    static const json kNull;
    if (!object.is_object()) {
        return kNull;
    }
    const auto it = object.find(key);
    return it == object.end() ? kNull : *it;
}

// RFC 4180: the field in double quotes, a double quote in it doubled.
std::string csv_quoted(std::string_view field) {
    std::string out = "\"";
    for (const char c : field) {
        out += c;
        if (c == '"') {
            out += '"';
        }
    }
    return out + "\"";
}

// A JSON number's own digits (-?d+(.d+)?(e[+-]d+)?), else nothing: a leading
// '-' is a sign and stays, and the field stays a number.
std::string number_field(const json& value) {
    return csv_quoted(value.is_number() ? value.dump() : "");
}

// The text field: printable, and a leading ' before what a spreadsheet would
// take for a formula (= + - @; OWASP's advice names a tab and a CR too, which
// printable has already written as \x09 and \x0d).
std::string text_field(const json& value) {
    auto text =
        printable(value.is_string() ? value.get<std::string>()
                  : value.is_null() ? ""
                                    : value.dump(-1, ' ', false, json::error_handler_t::replace));
    if (!text.empty() && std::string_view("=+-@").find(text.front()) != std::string::npos) {
        text.insert(0, 1, '\'');
    }
    return csv_quoted(text);
}

std::string angle_fields(const json& attitude, const char* source) {
    const auto& axes = member(attitude, source);
    return number_field(member(axes, "roll")) + "," + number_field(member(axes, "pitch")) + "," +
           number_field(member(axes, "yaw"));
}

std::optional<double> number_of(const json& value) {
    if (!value.is_number()) {
        return std::nullopt;
    }
    const auto number = value.get<double>();
    return std::isfinite(number) ? std::optional<double>(number) : std::nullopt;
}

// utc_us as an int64, when it is one.
std::optional<std::int64_t> int64_of(const json& us) {
    if (!us.is_number_integer() ||
        (us.is_number_unsigned() &&
         us.get<std::uint64_t>() > std::uint64_t{std::numeric_limits<std::int64_t>::max()})) {
        return std::nullopt;
    }
    return us.get<std::int64_t>();
}

CapturePosition position_of(const json& capture) {
    CapturePosition p;
    const auto& vehicle = member(capture, "vehicle");
    const json* from = &member(capture, "meta");
    const char* alt = "alt_m";
    if (vehicle.is_object()) {
        p.gps_utc_us = int64_of(member(vehicle, "utc_us"));
        const auto& tagged = member(vehicle, "tagged");
        if (!tagged.is_boolean() || !tagged.get<bool>()) {
            const auto& why = member(vehicle, "why");
            p.untagged = why.is_string() ? why.get<std::string>() : "untagged by gportd";
            return p;
        }
        from = &vehicle;
        alt = "alt_msl_m";
        p.h_acc_m = number_of(member(vehicle, "h_acc_m"));
        p.v_acc_m = number_of(member(vehicle, "v_acc_m"));
    }
    p.lat = number_of(member(*from, "lat"));
    p.lon = number_of(member(*from, "lon"));
    if (!p.lat || !p.lon || std::abs(*p.lat) > 90 || std::abs(*p.lon) > 180) {
        CapturePosition none;  // half a position, or one that does not exist
        none.gps_utc_us = p.gps_utc_us;
        return none;
    }
    p.alt_m = number_of(member(*from, alt));
    p.heading_deg = number_of(member(*from, "heading_deg"));
    p.from = from == &vehicle ? "vehicle" : "meta";
    return p;
}

std::string optional_field(const std::optional<double>& value) {
    return number_field(value ? json(*value) : json());
}

std::string position_fields(const CapturePosition& p) {
    const std::string position = p.untagged.empty() ? p.from : "untagged: " + p.untagged;
    return text_field(position) + "," + optional_field(p.lat) + "," + optional_field(p.lon) + "," +
           optional_field(p.alt_m) + "," + optional_field(p.h_acc_m) + "," +
           optional_field(p.v_acc_m) + "," + optional_field(p.heading_deg) + "," +
           csv_quoted(p.gps_utc_us ? utc_text(*p.gps_utc_us) : "");
}

// utc_us as text; empty unless it is an integer that fits an int64.
std::string utc_of(const json& capture) {
    const auto us = int64_of(member(capture, "utc_us"));
    return us ? utc_text(*us) : "";
}

json optional_json(const std::optional<double>& value) {
    return value ? json(*value) : json();
}

}  // namespace

CapturePosition capture_position(std::string_view capture) {
    return position_of(parsed(capture));
}

std::string captures_csv_header() {
    return "index,utc,kind,imu_roll,imu_pitch,imu_yaw,hall_roll,hall_pitch,hall_yaw,lat,lon,"
           "alt_m,position,position_lat,position_lon,position_alt_m,h_acc_m,v_acc_m,heading_deg,"
           "gps_utc\n";
}

std::string capture_csv_row(std::string_view text) {
    const auto capture = parsed(text);
    const auto& attitude = member(capture, "attitude");
    const auto& meta = member(capture, "meta");
    return number_field(member(capture, "index")) + "," + csv_quoted(utc_of(capture)) + "," +
           text_field(member(capture, "kind")) + "," + angle_fields(attitude, "imu") + "," +
           angle_fields(attitude, "hall") + "," + number_field(member(meta, "lat")) + "," +
           number_field(member(meta, "lon")) + "," + number_field(member(meta, "alt_m")) + "," +
           position_fields(position_of(capture)) + "\n";
}

std::string captures_geojson_head() {
    return R"({"type":"FeatureCollection","features":[)";
}

std::string captures_geojson_tail() {
    return "]}\n";
}

std::string capture_geojson_feature(std::string_view text) {
    const auto capture = parsed(text);
    const auto p = position_of(capture);
    if (p.from.empty()) {
        return "";
    }
    json coordinates = {*p.lon, *p.lat};
    if (p.alt_m) {
        coordinates.push_back(*p.alt_m);
    }
    const auto utc = utc_of(capture);
    const json feature = {{"type", "Feature"},
                          {"geometry", {{"type", "Point"}, {"coordinates", coordinates}}},
                          {"properties",
                           {{"index", member(capture, "index")},
                            {"utc", utc.empty() ? json() : json(utc)},
                            {"kind", member(capture, "kind")},
                            {"attitude", member(capture, "attitude")},
                            {"position", p.from},
                            {"h_acc_m", optional_json(p.h_acc_m)},
                            {"v_acc_m", optional_json(p.v_acc_m)},
                            {"heading_deg", optional_json(p.heading_deg)},
                            {"gps_utc", p.gps_utc_us ? json(utc_text(*p.gps_utc_us)) : json()}}}};
    return feature.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string utc_text(std::int64_t utc_us) {
    const auto t = base::civil_time(utc_us);
    char out[64];
    std::snprintf(out, sizeof(out), "%04lld-%02u-%02uT%02u:%02u:%02u.%06lldZ",
                  static_cast<long long>(t.year), t.month, t.day, t.hour, t.minute, t.second,
                  static_cast<long long>(t.micros));
    return out;
}

}  // namespace gport::client
