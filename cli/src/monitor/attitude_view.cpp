#include "attitude_view.hpp"

#include <fmt/format.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "text.hpp"

namespace gport::cli::monitor {
namespace {

constexpr Style kLineStyle{.fg = Color::kDefault, .bold = true};
constexpr Style kGroundStyle{.fg = Color::kYellow};
constexpr Style kMarkStyle{.fg = Color::kCyan, .bold = true};
constexpr Style kTapeStyle{.fg = Color::kGrey};

// Braille dot bits by (column 0-1, row 0-3) in a cell (Unicode U+2800 block).
constexpr unsigned kDotBits[2][4] = {{0x01, 0x02, 0x04, 0x40}, {0x08, 0x10, 0x20, 0x80}};

std::string braille(unsigned bits) {
    const unsigned code = 0x2800 + bits;  // three UTF-8 bytes: E2 A0..A3 80..BF
    std::string out;
    out += static_cast<char>(0xE0 | (code >> 12));
    out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (code & 0x3F));
    return out;
}

double radians(double degrees) {
    return degrees * std::numbers::pi / 180.0;
}

// Bits set in one cell for the line and for the ground pattern.
struct CellDots {
    unsigned line = 0;
    unsigned ground = 0;
};

// The horizon as a signed distance in dots: > 0.5 ground, |d| <= 0.5 the
// line, < -0.5 sky. The normal (sin roll, cos roll) points to the ground.
CellDots dots_of_cell(int cell_x, int cell_y, double cx, double cy, double roll, double shift) {
    CellDots dots;
    const double nx = std::sin(roll);
    const double ny = std::cos(roll);
    for (int dx = 0; dx < 2; ++dx) {
        for (int dy = 0; dy < 4; ++dy) {
            const int x = cell_x * 2 + dx;
            const int y = cell_y * 4 + dy;
            const double d = (x - cx) * nx + (y - cy) * ny - shift;
            if (std::fabs(d) <= 0.5) {
                dots.line |= kDotBits[dx][dy];
            } else if (d > 0.5 && x % 2 == 0 && y % 2 == 0) {
                dots.ground |= kDotBits[dx][dy];
            }
        }
    }
    return dots;
}

// The ASCII character for a cell of the horizon line tilted by `roll_deg`
// (rolled right: its right side rises, '/').
std::string ascii_line(double roll_deg) {
    double tilt = std::fmod(roll_deg, 180.0);  // the line looks the same turned by 180°
    if (tilt > 90.0) {
        tilt -= 180.0;
    } else if (tilt <= -90.0) {
        tilt += 180.0;
    }
    if (std::fabs(tilt) <= 22.5) {
        return "-";
    }
    if (std::fabs(tilt) >= 67.5) {
        return "|";
    }
    return tilt > 0 ? "/" : "\\";
}

}  // namespace

double wrap_degrees(double degrees) {
    double wrapped = std::fmod(degrees, 360.0);
    if (wrapped <= -180.0) {
        wrapped += 360.0;
    } else if (wrapped > 180.0) {
        wrapped -= 360.0;
    }
    return wrapped;
}

void draw_horizon(Screen& screen, const Box& box, double roll_deg, double pitch_deg, bool ascii) {
    if (box.width < 3 || box.height < 1) {
        return;
    }
    const double cx = box.width - 0.5;  // centre in dots: 2 per column, 4 per row
    const double cy = box.height * 2.0 - 0.5;
    const double half_height = box.height * 2.0;
    const double shift = pitch_deg / kHorizonFullScaleDeg * half_height;
    const double roll = radians(roll_deg);
    for (int y = 0; y < box.height; ++y) {
        for (int x = 0; x < box.width; ++x) {
            const CellDots dots = dots_of_cell(x, y, cx, cy, roll, shift);
            const unsigned bits = dots.line | dots.ground;
            if (bits == 0) {
                screen.set(box.row + y, box.col + x, " ");
            } else if (ascii) {
                screen.set(box.row + y, box.col + x, dots.line != 0 ? ascii_line(roll_deg) : ".",
                           dots.line != 0 ? kLineStyle : kGroundStyle);
            } else {
                screen.set(box.row + y, box.col + x, braille(bits),
                           dots.line != 0 ? kLineStyle : kGroundStyle);
            }
        }
    }
    // The aircraft: fixed at the centre, wings level with the screen.
    const int mid_row = box.row + box.height / 2 - (box.height % 2 == 0 ? 1 : 0);
    const int mid_col = box.col + box.width / 2 - 2;
    screen.put(mid_row, mid_col, "━━╋━━", kMarkStyle);
}

void draw_heading_tape(Screen& screen, const Box& box, double yaw_deg) {
    const int mid = box.width / 2;
    std::vector<std::pair<int, int>> labels;  // column, degrees
    for (int x = 0; x < box.width; ++x) {
        // The degrees this column covers: [from, from + step).
        const double from = yaw_deg + (x - mid - 0.5) * kTapeDegPerColumn;
        const int mark10 = static_cast<int>(std::ceil(from / 10.0)) * 10;
        std::string glyph = "─";
        if (mark10 < from + kTapeDegPerColumn) {
            const bool thirty = mark10 % 30 == 0;
            glyph = thirty ? "┼" : "┬";
            if (thirty) {
                labels.emplace_back(x, static_cast<int>(wrap_degrees(mark10)));
            }
        }
        screen.set(box.row, box.col + x, glyph, kTapeStyle);
    }
    screen.set(box.row, box.col + mid, "▲", kMarkStyle);
    // The heading itself under the pointer; the scale's labels around it.
    const std::string heading = fmt::format("yaw {}", signed_value(yaw_deg, 1, "°"));
    const int heading_start = mid - columns(heading) / 2;
    const int heading_end = heading_start + columns(heading);
    screen.put(box.row + 1, box.col + std::max(heading_start, 0), heading, kMarkStyle, box.width);
    for (const auto& [x, degrees] : labels) {
        const std::string text = fmt::format("{}", degrees);
        const int start = x - static_cast<int>(text.size()) / 2;
        const int end = start + static_cast<int>(text.size());
        const bool clear = end < heading_start || start > heading_end;
        if (start >= 0 && end <= box.width && clear) {
            screen.put(box.row + 1, box.col + start, text, kTapeStyle);
        }
    }
}

}  // namespace gport::cli::monitor
