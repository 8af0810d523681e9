// bench_relay_stop's command line: which scenarios, how many stops, how long
// the floods run before the probe, the programs, and an optional budget.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace gport::bench::relay {

// One scenario: the relay the probe's stops go through and the flood beside it.
struct Scenario {
    std::string name;   // "web/view-status", ...
    std::string relay;  // "web" or "mavlink"
    std::string flood;  // "none", "view-status", "view-mixed", "csv", "jog", "gcs-camera", ...
};

struct Options {
    int stops = 20;
    double flood_seconds = 1.0;  // the flood runs this long before the first stop
    int spacing_ms = 100;        // idle time between a stop on the wire and the next motion
    std::vector<Scenario> scenarios;
    std::string gportd = GPORT_BENCH_GPORTD;
    std::string gport_web = GPORT_BENCH_GPORT_WEB;
    std::string gport_mavlink = GPORT_BENCH_GPORT_MAVLINK;
    std::optional<double> budget_p99_ms;
    std::optional<double> budget_max_ms;
    bool fail_on_lost = false;  // exit 1 on a lost stop (implied by a budget)
    bool keep_logs = false;
};

// Every scenario, in the order they run.
const std::vector<Scenario>& all_scenarios();

// Parses argv; throws std::invalid_argument naming the option and what is
// allowed. Returns nullopt after printing --help.
std::optional<Options> parse_options(int argc, char** argv);

}  // namespace gport::bench::relay
