#include "gport/cli/captures.hpp"

#include <fmt/format.h>
#include <time.h>

#include <string_view>

#include "gport/cli/printable.hpp"

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

// A non-negative integer (parsed JSON holds one as unsigned, a built one
// may hold it as signed).
std::optional<std::uint64_t> index_of(const json& value) {
    if (value.is_number_unsigned() ||
        (value.is_number_integer() && value.get<std::int64_t>() >= 0)) {
        return value.get<std::uint64_t>();
    }
    return std::nullopt;
}

std::string utc_of(const json& capture) {
    const auto& us = member(capture, "utc_us");
    return us.is_number_integer() ? utc_text(us.get<std::int64_t>()) : std::string();
}

// A string as it is, anything else but null as JSON; printable either way.
std::string text(const json& value) {
    return printable(value.is_string() ? value.get<std::string>()
                     : value.is_null() ? ""
                                       : json_line(value));
}

// RFC 4180: every field in double quotes, a double quote in it doubled.
std::string csv_field(const std::string& field) {
    std::string out = "\"";
    for (const char c : field) {
        out += c == '"' ? "\"\"" : std::string(1, c);
    }
    return out + "\"";
}

// A text cell: a spreadsheet takes a cell starting with = + - @ (or a tab or
// CR) as a formula; a leading ' makes it text, as OWASP advises.
std::string text_cell(const json& value) {
    auto cell = text(value);
    if (!cell.empty() && std::string_view("=+-@\t\r").find(cell.front()) != std::string::npos) {
        cell.insert(0, 1, '\'');
    }
    return csv_field(cell);
}

// A number cell: only a JSON number's own digits (-?d+(.d+)?(e[+-]d+)?), so
// a leading '-' is a sign and stays, and the cell stays a number; any
// other value leaves it empty.
std::string number_cell(const json& value) {
    return csv_field(number(value));
}

std::string angle_cells(const json& attitude, const char* part) {
    const auto& axes = member(attitude, part);
    return fmt::format("{},{},{}", number_cell(member(axes, "roll")),
                       number_cell(member(axes, "pitch")), number_cell(member(axes, "yaw")));
}

}  // namespace

CapturesPage read_captures_page(const json& result, std::uint64_t since) {
    CapturesPage page;
    page.next = since;
    if (const auto& list = member(result, "captures"); list.is_array()) {
        page.captures.assign(list.begin(), list.end());
    }
    if (const auto next = index_of(member(result, "next"))) {
        page.next = *next;
    }
    const auto& more = member(result, "more");
    page.more =
        (more.is_boolean() ? more.get<bool>() : !page.captures.empty()) && page.next > since;
    return page;
}

std::optional<std::uint64_t> capture_index(const json& capture) {
    return index_of(member(capture, "index"));
}

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
    // kind comes from the log as written: a crafted one is a text cell like any.
    return fmt::format("{},{},{},{},{},{},{},{}\n", number_cell(member(capture, "index")),
                       csv_field(utc_of(capture)), text_cell(member(capture, "kind")),
                       angle_cells(attitude, "imu"), angle_cells(attitude, "hall"),
                       number_cell(member(meta, "lat")), number_cell(member(meta, "lon")),
                       number_cell(member(meta, "alt_m")));
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
    const auto who = fmt::format("{}(pid {})", name.is_string() ? text(name) + " " : "",
                                 text(member(client, "pid")));
    return fmt::format("{:>7}  {:<27}  {:<13}  {:<24}  {:<24}  {}\n",
                       number(member(capture, "index")), utc_of(capture),
                       text(member(capture, "kind")), axes("imu"), axes("hall"), who);
}

}  // namespace gport::cli
