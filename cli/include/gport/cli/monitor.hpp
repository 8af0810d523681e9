// gportctl monitor: a full-screen live view of the gimbal and the daemon
// (docs/monitor.md). The one entry point gportctl's parser calls.
#pragma once

#include <chrono>
#include <functional>
#include <optional>
#include <ostream>
#include <string>

namespace gport::cli {

enum class ColorMode { kAuto, kAlways, kNever };

struct MonitorOptions {
    std::string socket;                                 // gportd's socket
    bool control = false;                               // --control: acquire; arrows nudge
    std::optional<std::chrono::milliseconds> duration;  // --for: end after it
    ColorMode color = ColorMode::kAuto;                 // auto: colour unless $NO_COLOR
    bool ascii = false;  // --ascii: ASCII only, as in a locale that is not UTF-8
};

// Runs until q, Ctrl-C/SIGTERM (`interrupted` turns true) or the duration.
// On a terminal: the full-screen view on stdout (the terminal is restored
// on every way out). Otherwise: a plain status block on `out` each second.
// Returns the exit status: 0, 69 when gportd cannot be reached at the start,
// 1 when --control cannot acquire control or the terminal cannot be set up.
int run_monitor(const MonitorOptions& options, std::ostream& out, std::ostream& err,
                const std::function<bool()>& interrupted);

}  // namespace gport::cli
