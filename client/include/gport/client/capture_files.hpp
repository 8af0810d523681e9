// The capture log as files for geotagging (1.8.0): CSV and GeoJSON, the one
// writer behind gportctl captures --csv and gport-web's /api/captures.csv and
// /api/captures.geojson, so that they are byte for byte the same
// (docs/api.md, "The capture log as CSV and GeoJSON").
//
// Each function takes one capture as the JSON text gportd lists it (an
// element of the captures result's `captures`, or a capture notification's
// params) and is lenient about its shape, as a geotagger reading an old or
// odd log wants: a member that is missing or of another type gives an empty
// field, never an error. Only text that is not JSON at all throws Error
// (kBadReply), naming the capture.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "gport/client/error.hpp"
#include "gport/client/export.hpp"

namespace gport::client {

// Where a capture was taken (1.11.0), by the one rule of every writer (the
// CSV's position columns, the GeoJSON, gportctl geotag):
// - gportd tagged it (its `vehicle` has "tagged": true): the vehicle's
//   position at the shutter, with its accuracy and heading; from "vehicle";
// - gportd marked it untagged (no position recent enough, no fix...): no
//   position, never the caller's meta, whose position is no better;
//   `untagged` holds gportd's reason;
// - gportd had no vehicle source (no `vehicle`, or null): the caller's meta
//   (lat, lon, alt_m), as before 1.10.0; from "meta".
// A latitude beyond ±90°, a longitude beyond ±180° or half a position is no
// position. gps_utc_us: the autopilot's UTC at the shutter, when gportd
// knew it (tagged or not).
struct CapturePosition {
    std::optional<double> lat{}, lon{}, alt_m{};  // degrees; metres above mean sea level
    std::optional<double> h_acc_m{}, v_acc_m{};   // 1-sigma, from "vehicle" only
    std::optional<double> heading_deg{};          // the vehicle's (the meta's when from it)
    std::optional<std::int64_t> gps_utc_us{};
    std::string from{};      // "vehicle", "meta", or empty: no position
    std::string untagged{};  // gportd's reason, when it marked the capture untagged
};
GPORT_CLIENT_API CapturePosition capture_position(std::string_view capture);

// "index,utc,kind,imu_roll,imu_pitch,imu_yaw,hall_roll,hall_pitch,hall_yaw,lat,lon,alt_m,
// position,position_lat,position_lon,position_alt_m,h_acc_m,v_acc_m,heading_deg,gps_utc\n":
// the header line, its names unquoted. lat, lon and alt_m are the meta's as
// the caller gave them; position is capture_position's `from` ("vehicle",
// "meta"), "untagged: " and gportd's reason, or empty; the position_ columns
// and the rest are capture_position's (gps_utc as utc_text) (1.11.0).
GPORT_CLIENT_API std::string captures_csv_header();

// One row, ending in "\n" (LF, as the header; not RFC 4180's CRLF). Every
// field is in double quotes, a double quote in it doubled (RFC 4180), the
// number fields too. utc: utc_text(utc_us), empty unless utc_us is an
// integer. The number fields (index, the attitude's imu and hall
// roll/pitch/yaw in degrees, meta's lat, lon and alt_m) hold a JSON number
// as JSON writes it (shortest round trip: -30.5, 12, 1e+300) or nothing: a
// string in meta's lat is left out. kind, the one text field, is its string
// (any other value but null: its JSON text) through printable(), so no row
// holds a control character or a line break (a tab is "\x09", a CR
// "\x0d"), and gets a leading ' when it starts with = + - or @, so no
// spreadsheet takes it for a formula.
GPORT_CLIENT_API std::string capture_csv_row(std::string_view capture);

// A GeoJSON FeatureCollection (RFC 7946) is the head, the features
// separated by ",", and the tail.
GPORT_CLIENT_API std::string captures_geojson_head();  // {"type":"FeatureCollection","features":[
GPORT_CLIENT_API std::string captures_geojson_tail();  // ]}\n
// A Point feature at capture_position's lon, lat (and alt_m when known),
// with the properties index, utc (as in the CSV; null without one), kind and
// attitude as gportd logged them, and (1.11.0) position (its `from`),
// h_acc_m, v_acc_m, heading_deg and gps_utc (null when unknown); empty when
// the capture has no position.
GPORT_CLIENT_API std::string capture_geojson_feature(std::string_view capture);

// ISO 8601 UTC with microseconds: 1795563183085470 ->
// "2026-11-24T23:33:03.085470Z", -1 -> "1969-12-31T23:59:59.999999Z". A
// year past 9999 has more digits, one before year 0 a '-'.
GPORT_CLIENT_API std::string utc_text(std::int64_t utc_us);

}  // namespace gport::client
