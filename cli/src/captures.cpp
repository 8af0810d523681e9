#include "gport/cli/captures.hpp"

#include <fmt/format.h>
#include <time.h>

namespace gport::cli {
namespace {

using nlohmann::json;

const json& member(const json& object, const char* key) {
    static const json kNull;
    if (!object.is_object()) {
        return kNull;
    }
    const auto it = object.find(key);
    return it == object.end() ? kNull : *it;
}

// A number as JSON prints it (shortest round trip), else empty.
std::string number(const json& value) {
    return value.is_number() ? value.dump() : std::string();
}

std::string utc_of(const json& capture) {
    const auto& us = member(capture, "utc_us");
    return us.is_number_integer() ? utc_text(us.get<std::int64_t>()) : std::string();
}

std::string angle_cells(const json& attitude, const char* part) {
    const auto& axes = member(attitude, part);
    return fmt::format("{},{},{}", number(member(axes, "roll")), number(member(axes, "pitch")),
                       number(member(axes, "yaw")));
}

std::string text(const json& value) {
    return value.is_string() ? value.get<std::string>() : value.is_null() ? "" : value.dump();
}

}  // namespace

std::string utc_text(std::int64_t utc_us) {
    const auto seconds =
        static_cast<time_t>(utc_us >= 0 ? utc_us / 1000000 : (utc_us - 999999) / 1000000);
    const auto micros = utc_us - static_cast<std::int64_t>(seconds) * 1000000;
    struct tm tm {};
    gmtime_r(&seconds, &tm);
    return fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}.{:06}Z", tm.tm_year + 1900,
                       tm.tm_mon + 1, tm.tm_mday, tm.tm_hour, tm.tm_min, tm.tm_sec, micros);
}

std::string captures_csv_header() {
    return "index,utc,kind,imu_roll,imu_pitch,imu_yaw,hall_roll,hall_pitch,hall_yaw,lat,lon,"
           "alt_m\n";
}

std::string capture_csv_row(const json& capture) {
    const auto& attitude = member(capture, "attitude");
    const auto& meta = member(capture, "meta");
    // kind is one of gportd's words (no comma, no quote): no CSV quoting needed.
    return fmt::format("{},{},{},{},{},{},{},{}\n", number(member(capture, "index")),
                       utc_of(capture), text(member(capture, "kind")), angle_cells(attitude, "imu"),
                       angle_cells(attitude, "hall"), number(member(meta, "lat")),
                       number(member(meta, "lon")), number(member(meta, "alt_m")));
}

std::string captures_table_header() {
    return fmt::format("{:>7}  {:<27}  {:<13}  {:<24}  {:<24}  {}\n", "INDEX", "UTC", "KIND",
                       "IMU ROLL/PITCH/YAW", "HALL ROLL/PITCH/YAW", "CLIENT");
}

std::string capture_table_row(const json& capture) {
    const auto& attitude = member(capture, "attitude");
    const auto axes = [&](const char* part) {
        if (attitude.is_null()) {
            return std::string("-");
        }
        const auto& a = member(attitude, part);
        return fmt::format("{}/{}/{}", number(member(a, "roll")), number(member(a, "pitch")),
                           number(member(a, "yaw")));
    };
    const auto& client = member(capture, "client");
    const auto& name = member(client, "name");
    const auto who = fmt::format("{}{}", name.is_string() ? name.get<std::string>() + " " : "",
                                 fmt::format("(pid {})", text(member(client, "pid"))));
    return fmt::format("{:>7}  {:<27}  {:<13}  {:<24}  {:<24}  {}\n",
                       number(member(capture, "index")), utc_of(capture),
                       text(member(capture, "kind")), axes("imu"), axes("hall"), who);
}

}  // namespace gport::cli
