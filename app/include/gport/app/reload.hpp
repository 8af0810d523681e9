// SIGHUP: what a re-read configuration changes while the daemon runs.
//
// Only a few keys can change safely without reopening the device or the
// socket: the log level, who may command (access.*), and the default and
// longest speed durations, the soft limits and
// the failsafe policies. Every other changed key is reported as needing a
// restart and keeps its running value.
#pragma once

#include <string>
#include <vector>

#include "gport/config/config.hpp"

namespace gport::app {

struct ReloadPlan {
    config::Config in_effect;               // the running config with the live keys applied
    std::vector<std::string> applied;       // changed keys that take effect now
    std::vector<std::string> need_restart;  // changed keys that do not, until a restart
};

// Compares key by key (names as in the file, e.g. "keepalive.max_duration_ms").
ReloadPlan plan_reload(const config::Config& running, const config::Config& next);

}  // namespace gport::app
