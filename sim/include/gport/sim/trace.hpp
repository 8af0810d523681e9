// The simulator's trace: one JSON object per line, a stable format that
// integration tests parse (docs/simulator.md lists every field).
//
//   {"t_ms":1234.5,"cmd":"0x85","mode":"speed","angle":[0,0,0],"speed":[0,0,3000]}
//   {"t_ms":1240.1,"event":"bad_frame","kind":"crc"}
//   {"t_ms":2000.0,"event":"vanish","path":"/tmp/gimbal"}
//
// t_ms is milliseconds since the simulator started, to 0.1 ms. Lines with
// "cmd" are valid frames received from the client; lines with "event" are
// everything else. Angles and speeds are the wire's raw 0.01° / 0.01°/s.
#pragma once

#include <string>
#include <string_view>

#include "gport/sim/model.hpp"

namespace gport::sim {

// The line (without newline) for something the model received.
std::string trace_received(double t_ms, const Received& received);
// The line for a simulator event such as "vanish", "reappear", "peer_open".
// `path` and `error` are added when not empty.
std::string trace_event(double t_ms, std::string_view event, std::string_view path = {},
                        std::string_view error = {});

}  // namespace gport::sim
