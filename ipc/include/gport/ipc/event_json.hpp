// JSON encoding of the core's events as notification lines (sway's ipc-json
// beside its ipc-server). A line is built once per event and shared by every
// subscriber, hence std::shared_ptr<const std::string>.
//
// Attitude payload (docs/api.md, "Notifications"; written by
// gport/contract/attitude_text.hpp): degrees from the wire's 0.01 units,
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

#include "gport/contract/attitude_text.hpp"
#include "gport/daemon/api.hpp"

namespace gport::ipc {

using Line = std::shared_ptr<const std::string>;

// An attitude notification: its line, built once and shared by every
// subscriber, and the payload it was built from, from which a client that
// lost samples gets its own line with "dropped" (with_dropped).
struct AttitudeNotification {
    std::string text;  // the whole line, ending in '\n'
    contract::AttitudePayload payload;
};
using AttitudeLine = std::shared_ptr<const AttitudeNotification>;

// The sample as the contract's attitude text prints it
// (gport/contract/attitude_text.hpp): degrees, microseconds.
contract::AttitudePayload attitude_payload_of(const daemon::AttitudeSample& sample);
// The attitude payload object as JSON text (no newline).
std::string attitude_payload(const daemon::AttitudeSample& sample);

// Whole notification lines, ending in '\n'.
AttitudeLine attitude_line(const daemon::AttitudeSample& sample);
Line link_line(const daemon::LinkEvent& event);
Line motion_line(const daemon::MotionEvent& event);
// A `capture` notification: its params are the capture as `captures` lists it.
Line capture_line(std::string_view capture);

// The shared line itself (sharing its ownership, not a copy).
Line text_of(const AttitudeLine& notification);
// The notification built again with "dropped":<count> in its params: how
// this one client learns how many samples it has lost so far.
Line with_dropped(const AttitudeNotification& notification, std::uint64_t dropped);

// The same payload as a JSON object, for results that add to it (the
// `attitude` method adds "age_ms"); it serialises to the same values.
nlohmann::json attitude_json(const daemon::AttitudeSample& sample);

}  // namespace gport::ipc
