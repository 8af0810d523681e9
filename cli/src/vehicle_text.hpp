// The vehicle in gportctl's output (docs/api.md, "The vehicle"): status's
// line, and what a photo or record toggle was stamped with.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace gport::cli {

// "vehicle:   ..." and a newline, from a status result; what a server that
// lies sends is shown as unknown, never trusted.
std::string vehicle_status_line(const nlohmann::json& status);
// ", at 47.3977427, 8.5455941 (±1.2 m)" or ", untagged: why" for a photo or
// record result's capture; "" when it has no vehicle.
std::string capture_vehicle_suffix(const nlohmann::json& result);

}  // namespace gport::cli
