#include "gport/cli/captures.hpp"

#include <fmt/format.h>

#include <limits>
#include <string_view>

#include "gport/cli/printable.hpp"
#include "gport/client/capture_files.hpp"

namespace gport::cli {
namespace {

using nlohmann::json;

constexpr std::string_view kTableRow = "{:>7}  {:<27}  {:<13}  {:<24}  {:<24}  {:<26}  {}\n";

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
    if (us.is_number_unsigned() &&
        us.get<std::uint64_t>() > std::uint64_t{std::numeric_limits<std::int64_t>::max()}) {
        return "";
    }
    return us.is_number_integer() ? client::utc_text(us.get<std::int64_t>()) : std::string();
}

// A string as it is, anything else but null as JSON; printable either way.
std::string text(const json& value) {
    return printable(value.is_string() ? value.get<std::string>()
                     : value.is_null() ? ""
                                       : json_line(value));
}

// A meta member of the position: a number as JSON writes it, "?" when
// missing, anything else as its JSON text, printable.
std::string position_part(const json& value) {
    return value.is_number() ? value.dump() : value.is_null() ? "?" : printable(json_line(value));
}

std::string position_of(const json& capture) {
    const auto& meta = member(capture, "meta");
    const auto& lat = member(meta, "lat");
    const auto& lon = member(meta, "lon");
    const auto& alt = member(meta, "alt_m");
    if (lat.is_null() && lon.is_null() && alt.is_null()) {
        return "-";
    }
    const auto where = position_part(lat) + "," + position_part(lon);
    return alt.is_null() ? where : where + " " + position_part(alt) + "m";
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

std::string capture_csv_row(const json& capture) {
    return client::capture_csv_row(capture.dump(-1, ' ', false, json::error_handler_t::replace));
}

std::string captures_table_header() {
    return fmt::format(kTableRow, "INDEX", "UTC", "KIND", "IMU ROLL/PITCH/YAW",
                       "HALL ROLL/PITCH/YAW", "POSITION", "CLIENT");
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
    return fmt::format(kTableRow, number(member(capture, "index")), utc_of(capture),
                       text(member(capture, "kind")), axes("imu"), axes("hall"),
                       position_of(capture), who);
}

}  // namespace gport::cli
