// The monitor's text lines: each piece of the model as short lines, shared by
// the full-screen layouts and the plain status block.
#pragma once

#include <string>
#include <vector>

#include "screen.hpp"
#include "state.hpp"

namespace gport::cli::monitor {

// A run of text with one style; a line is a sequence of spans.
struct Span {
    std::string text{};
    Style style{};
};
using Line = std::vector<Span>;

inline constexpr Style kLabel{.fg = Color::kGrey};
inline constexpr Style kTitle{.fg = Color::kCyan, .bold = true};
inline constexpr Style kValue{};
// Values from before the connection was lost, and the mark saying so.
inline constexpr Style kStale{.fg = Color::kGrey, .dim = true};
inline constexpr Style kStaleMark{.fg = Color::kYellow, .bold = true};

Style severity_style(Severity severity);
Style link_style(const std::string& state);

// "IMU    +12.34°  -30.00°  +45.00°" under a "roll pitch yaw" header (the
// wide table), or without attitude one line saying so.
std::vector<Line> angle_table(const MonitorModel& model);
// "IMU  r +12.3 p -30.0 y +45.0 °" (narrow).
std::vector<Line> angle_lines_compact(const MonitorModel& model);
// "speed  yaw +30.0 °/s" / "owner  you · 1.4 s left" / "last   angle: reached".
std::vector<Line> motion_lines(const MonitorModel& model);
// Control holder, counters, drops, clients.
std::vector<Line> daemon_lines(const MonitorModel& model);
// "● UP  attitude arriving · last sample 12 ms ago · /dev/pts/1".
Line link_line(const MonitorModel& model);
// Why gportd cannot be reached, "reason  " and the whole message wrapped to
// `width` columns in at most `max_rows` lines (cut with "…" only beyond).
std::vector<Line> reason_lines(const MonitorModel& model, int width, int max_rows);
// The key help for the bottom row.
Line key_line(const MonitorModel& model);
// "12:03:04  link down: ..." for one event.
Line event_line(const EventLine& event);

// Writes a line at (row, col), clipped to `width` columns; returns columns used.
int put_line(Screen& screen, int row, int col, const Line& line, int width);
// The line as plain text.
std::string line_text(const Line& line);

}  // namespace gport::cli::monitor
