// One line per scenario: stops sent, seen on the wire, lost, p50 / p99 / max
// (ms, stop sent -> its zero-speed 0x85 fully on the gimbal's wire), the
// motions gportd itself ended on their lease meanwhile, the flood's rate,
// whether the relay lost gportd, and whether it still runs.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>

#include "options.hpp"
#include "relay_probe.hpp"

namespace gport::bench::relay {

struct ScenarioResult {
    Scenario scenario;
    ProbeResult probe;
    std::uint64_t lease_endings = 0;  // zero speeds that were gportd's deadman
    int relay_drops = 0;              // the relay's "lost gportd" log lines added
    bool relay_alive = true;
    std::string flood_rate;  // e.g. "4210 req/s"
    std::string notes;       // refused stops, closed sockets, ...
};

void print_header(std::ostream& out);
void print_row(std::ostream& out, ScenarioResult& result);

// Why the result breaks the budget or the rules ("" when it does not):
// a relay that died always; lost stops with --fail-on-lost or a budget;
// p99 and max over --budget-p99-ms / --budget-max-ms.
std::string verdict(ScenarioResult& result, const Options& options);

}  // namespace gport::bench::relay
