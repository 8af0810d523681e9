// JSON encoding of the core's events as notification lines (sway's ipc-json
// beside its ipc-server). A line is built once per event and shared by every
// subscriber, hence std::shared_ptr<const std::string>.
//
// Attitude payload (docs/api.md, "Notifications"): degrees from the wire's 0.01 units,
// "t" as seconds since the epoch with microseconds, "rates" only when the
// gimbal sent the 24-byte form:
//   {"seq":1042,"t":1763770000.123456,
//    "imu":{"roll":0,"pitch":0,"yaw":-39.29},"hall":{"roll":-19.21,...},
//    "rates":{"hall":{"roll":1.25,...},"imu":{"x":0.12,"y":-2.3,"z":0}}}
#pragma once

#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "gport/daemon/api.hpp"

namespace gport::ipc {

using Line = std::shared_ptr<const std::string>;

// The attitude payload object as JSON text (no newline).
std::string attitude_payload(const daemon::AttitudeSample& sample);

// Whole notification lines, ending in '\n'.
Line attitude_line(const daemon::AttitudeSample& sample);
Line link_line(const daemon::LinkEvent& event);
Line motion_line(const daemon::MotionEvent& event);
// A `capture` notification: its params are the capture as `captures` lists it.
Line capture_line(const nlohmann::json& capture);

// A copy of an attitude notification line with "dropped":<count> added to its
// params: how this one client learns how many samples it has lost so far.
Line with_dropped(const std::string& attitude_notification, std::uint64_t dropped);

// The same payload as a JSON object, for results that add to it (the
// `attitude` method adds "age_ms"); it serialises to the same values.
nlohmann::json attitude_json(const daemon::AttitudeSample& sample);

}  // namespace gport::ipc
