// The monitor's frames: a MonitorModel in, text out. Pure functions, tested
// at 80×24 and at small sizes; the terminal side only writes what they give.
#pragma once

#include <cstddef>
#include <string>

#include "charset.hpp"
#include "screen.hpp"
#include "state.hpp"

namespace gport::cli::monitor {

// Below these, the narrow single-column layout (no attitude indicator).
inline constexpr int kWideMinWidth = 72;
inline constexpr int kWideMinHeight = 20;
// Below these, only a "terminal too small" line.
inline constexpr int kMinWidth = 24;
inline constexpr int kMinHeight = 6;

// The nudge speed of the arrow keys (°/s), shown in the key help.
inline constexpr double kNudgeSpeedDegPerS = 20.0;

// The whole screen for a terminal of width × height; with kAscii, no
// character outside ASCII. Once gportd is gone, the last values it gave stay
// but faint, under titles marked "stale", and the reason shows whole.
Screen render(const MonitorModel& model, int width, int height, Charset charset = Charset::kUtf8);

// The plain status block printed once a second when stdout is not a
// terminal: a few "name: value" lines, then the `new_events` latest events,
// then an empty line. No escape sequences.
std::string render_plain(const MonitorModel& model, std::size_t new_events,
                         Charset charset = Charset::kUtf8);

}  // namespace gport::cli::monitor
