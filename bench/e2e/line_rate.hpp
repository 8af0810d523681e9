// bench_e2e --line-rate: the stop on the wire when the gimbal's side drains
// at a real UART's 115200 baud (11,520 bytes a second), idle and under the
// floods of issue 30. See docs/performance.md, "Stop at the line rate".
#pragma once

#include <sys/types.h>

#include <string>
#include <vector>

#include "options.hpp"

namespace gport::bench {

// One scenario: a flood (or none) from some connections, as some uid.
struct LineScenario {
    std::string name;   // "idle", "photo", "captures", "batches", "every", "vehicle"
    std::string flood;  // a FloodKind name; "" = none
    int connections = 0;
    bool read_only = false;  // the flood runs as the reader uid
    bool seeded = false;     // 1,000 captures with 1 KiB metas in the log first
};

// The scenarios --line-rate NAME[,NAME...] names ("all": every one).
std::vector<LineScenario> line_scenarios(const std::string& names);

// Writes `count` captures, each with a ~1 KiB meta, to DIR/captures.jsonl in
// the capture log's line format (docs/operations.md, "The capture log").
void seed_capture_log(const std::string& dir, int count);

int run_line_rate(const Options& options);

}  // namespace gport::bench
