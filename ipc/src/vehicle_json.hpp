// publish_vehicle, and the vehicle in captures and status (docs/api.md,
// "The vehicle").
#pragma once

#include <nlohmann/json.hpp>
#include <optional>

#include "gport/daemon/vehicle.hpp"
#include "methods.hpp"

namespace gport::ipc::detail {

// publish_vehicle's params as a report (InvalidParams naming the member and
// what it must be); the ranges are the core's to check.
daemon::VehicleReport vehicle_report(const nlohmann::json& params);
void publish_vehicle(MethodContext& c, const nlohmann::json& params, Respond respond);

// A capture's "vehicle": null when nothing ever published the vehicle.
nlohmann::json vehicle_stamp_json(const std::optional<daemon::VehicleStamp>& stamp);
// status's "vehicle": null when nothing was ever published or refused.
nlohmann::json vehicle_status_json(const std::optional<daemon::VehicleStatus>& status);

}  // namespace gport::ipc::detail
