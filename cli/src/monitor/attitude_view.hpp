// The attitude indicator: an artificial horizon for roll and pitch drawn
// with braille dots (2×4 per cell), and a heading tape for yaw.
#pragma once

#include "screen.hpp"

namespace gport::cli::monitor {

// The area of the screen a drawing takes.
struct Box {
    int row = 0;
    int col = 0;
    int width = 0;
    int height = 0;
};

// Pitch that moves the horizon from the centre to the top or bottom edge.
inline constexpr double kHorizonFullScaleDeg = 45.0;
// Degrees per column of the heading tape.
inline constexpr double kTapeDegPerColumn = 2.0;

// The horizon in `box`: the line through the centre tilted by `roll` and
// shifted by `pitch` (nose up moves it down), the ground below it dotted,
// the aircraft's mark fixed at the centre. `ascii`: the line drawn with
// - / \ | by its slope and the ground with dots, one character a cell.
void draw_horizon(Screen& screen, const Box& box, double roll_deg, double pitch_deg,
                  bool ascii = false);

// Two rows from box.row: ticks every 10° (┼ every 30°) with a ▲ at the
// centre, then the heading under it and labels every 30° (-180..180) around.
void draw_heading_tape(Screen& screen, const Box& box, double yaw_deg);

// -180 < result <= 180.
double wrap_degrees(double degrees);

}  // namespace gport::cli::monitor
