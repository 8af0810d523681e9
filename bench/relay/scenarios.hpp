// A scenario on each relay: its flood for --flood-seconds, then the probe's
// stops through the relay while the flood goes on.
#pragma once

#include "options.hpp"
#include "report.hpp"
#include "rig.hpp"

namespace gport::bench::relay {

// web: jog (yaw 5 °/s) on a control WebSocket; stops alternate between
// {"type":"stop"} on that socket and POST /api/stop on a keep-alive
// connection.
ScenarioResult run_web_scenario(Rig& rig, const Options& options, const Scenario& scenario);

// mavlink: as the vehicle (1/1), GIMBAL_DEVICE_SET_ATTITUDE with a NaN
// quaternion and a yaw rate of 0.1 rad/s to 1/154, then the zero rate.
ScenarioResult run_mavlink_scenario(Rig& rig, const Options& options, const Scenario& scenario);

}  // namespace gport::bench::relay
