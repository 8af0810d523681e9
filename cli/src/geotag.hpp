// photo and record's geotag options (issue 32): --lat, --lon, --alt and
// --meta become the request's `meta` (docs/api.md, "Captures"), the
// position under the names the capture log's CSV reads (lat, lon, alt_m).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "gport/base/result.hpp"

namespace gport::cli {

// --lat -90..90 and --lon -180..180 (checked by the parser), --alt metres.
struct GeotagArgs {
    std::optional<double> lat, lon, alt;
    std::optional<std::string> meta;  // --meta: a JSON object's text
};

// The `meta` to send (none when no option was given), or the usage error's
// message without the command's name: --lat without --lon (or the other
// way), --alt without both, --meta that is not a JSON object (or nests
// deeper than 32), or a key of --meta that an option also sets.
Result<std::optional<nlohmann::json>, std::string> geotag_meta(const GeotagArgs& args);

}  // namespace gport::cli
