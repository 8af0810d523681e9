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

// The CSV: libgport-client's capture_csv_row (gport/client/capture_files.hpp),
// gport-web's writer too; a capture that does not serialise (invalid UTF-8 in
// a built one) has U+FFFD in its place.
std::string capture_csv_row(const nlohmann::json& capture);

// The table for people: kind and the client's name printable(); utc as in
// the CSV; POSITION from meta's lat, lon and alt_m ("-" without any of
// them), each a number as JSON writes it, "?" when missing, else its JSON
// text made printable ("47.1,?" or "\"N47\",8.5 488m"), never an error.
std::string captures_table_header();
std::string capture_table_row(const nlohmann::json& capture);

}  // namespace gport::cli
