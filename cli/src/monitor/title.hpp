// The monitor's title bar: what it says at a given width. Priorities, from
// kept longest to dropped first (docs/monitor.md, "Title"): the socket's
// file name, the clock, the daemon's uptime, "gportctl monitor", gportd's
// version, the socket's directory (elided as "…/").
#pragma once

#include <string>

#include "state.hpp"

namespace gport::cli::monitor {

struct Title {
    std::string left{};   // " gportctl monitor · gportd 0.1.0 · /run/gportd.sock"
    std::string right{};  // "up 3m 05s  12:03:04 " (may be empty)
};

// The two parts for a title bar `width` columns wide: columns(left) + 1 +
// columns(right) <= width whenever width >= 3. `ascii`: "..." for "…".
Title title_for(const MonitorModel& model, int width, bool ascii);

}  // namespace gport::cli::monitor
