// gportd --probe [DEVICE...]: finds the G-Port among the serial devices
// (gport/daemon/probe.hpp) and prints what each one is. docs/operations.md,
// "Finding the gimbal".
#pragma once

#include <chrono>
#include <string>
#include <vector>

namespace gport::app {

// The whole of `gportd --probe`: `devices`, or when empty the usual serial
// devices (serial_candidates()). Prints the report to stdout; returns 0 when
// a G-Port was found, 1 when none was.
int run_probe(const std::vector<std::string>& devices,
              std::chrono::milliseconds listen = std::chrono::milliseconds(1500));

}  // namespace gport::app
