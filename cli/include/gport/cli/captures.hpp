// gportctl captures: the capture log as a table or as CSV for geotagging
// (docs/api.md, "Captures"). Lenient like every output: a capture of an
// unexpected shape prints empty cells, never throws.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

namespace gport::cli {

// "index,utc,kind,imu_roll,imu_pitch,imu_yaw,hall_roll,hall_pitch,hall_yaw,lat,lon,alt_m\n"
std::string captures_csv_header();
// One row: utc as ISO 8601 UTC with microseconds; the angles empty without an
// attitude; lat, lon, alt_m from meta's numbers of those names, else empty.
std::string capture_csv_row(const nlohmann::json& capture);

std::string captures_table_header();
std::string capture_table_row(const nlohmann::json& capture);

// 1795563183085470 -> "2026-11-24T23:33:03.085470Z".
std::string utc_text(std::int64_t utc_us);

}  // namespace gport::cli
