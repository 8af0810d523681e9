// gportctl captures: the capture log as a table or as CSV for geotagging
// (docs/api.md, "Captures"). Lenient like every output: a capture of an
// unexpected shape prints empty cells, never throws.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace gport::cli {

// One reply of the `captures` method, asked for from `since`.
struct CapturesPage {
    std::vector<nlohmann::json> captures;
    std::uint64_t next = 0;  // the `since` to ask for next (`since` when absent)
    bool more = false;       // ask again: captures at or after `next` exist
};

// Reads a reply leniently. `more` is the reply's when it is a boolean; from
// a gportd before byte-bounded pages (no `more`): the page was not empty.
// Either way, false unless `next` is past `since`: a page that does not
// advance ends the listing instead of asking for it again forever.
CapturesPage read_captures_page(const nlohmann::json& result, std::uint64_t since);

// A capture's index; none when it has no unsigned integer one.
std::optional<std::uint64_t> capture_index(const nlohmann::json& capture);

// "index,utc,kind,imu_roll,imu_pitch,imu_yaw,hall_roll,hall_pitch,hall_yaw,lat,lon,alt_m\n"
std::string captures_csv_header();
// One row: utc as ISO 8601 UTC with microseconds; the angles empty without an
// attitude; lat, lon, alt_m from meta's numbers of those names, else empty.
// RFC 4180: every field in double quotes (one inside doubled). Number
// columns hold a JSON number's own digits or nothing; the text column
// (kind) is printable() and gets a leading ' when it starts with
// = + - @, a tab or a CR, so no spreadsheet takes it for a formula.
std::string capture_csv_row(const nlohmann::json& capture);

// The table for people: kind and the client's name printable().
std::string captures_table_header();
std::string capture_table_row(const nlohmann::json& capture);

// 1795563183085470 -> "2026-11-24T23:33:03.085470Z".
std::string utc_text(std::int64_t utc_us);

}  // namespace gport::cli
