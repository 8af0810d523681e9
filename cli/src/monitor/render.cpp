#include "render.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "attitude_view.hpp"
#include "charset.hpp"
#include "lines.hpp"
#include "text.hpp"
#include "title.hpp"

namespace gport::cli::monitor {
namespace {

constexpr Style kHeader{.bold = true, .reverse = true};
constexpr Style kBorder{.fg = Color::kGrey};

// The title bar: program, daemon, socket on the left; uptime and clock right
// (title.hpp says what goes first when the width runs short).
void draw_header(Screen& screen, const MonitorModel& model, bool ascii) {
    const int width = screen.width();
    screen.put(0, 0, std::string(static_cast<std::size_t>(width), ' '), kHeader);
    const Title title = title_for(model, width, ascii);
    screen.put(0, 0, title.left, kHeader, width);
    if (!title.right.empty()) {
        screen.put(0, width - columns(title.right), title.right, kHeader);
    }
}

// What a section's title says: " · stale" once gportd is gone.
std::string section_title(const MonitorModel& model, const std::string& title) {
    return model.connected ? title : title + " · stale";
}

// Values from before the connection was lost: every cell of rows [from, to)
// faint, but for the marks that say so.
void dim_rows(Screen& screen, int from, int to) {
    for (int row = std::max(from, 0); row < std::min(to, screen.height()); ++row) {
        for (int col = 0; col < screen.width(); ++col) {
            const Cell& cell = screen.at(row, col);
            if (cell.style != kStaleMark) {
                screen.set(row, col, std::string(cell.glyph), kStale);
            }
        }
    }
}

// " Angles " in the title style; a " · stale" end in the stale mark's.
void put_title(Screen& screen, int row, int col, const std::string& title, int limit) {
    const std::string stale = " · stale";
    const bool marked = title.size() > stale.size() && title.ends_with(stale);
    const std::string plain = marked ? title.substr(0, title.size() - stale.size()) : title;
    put_line(screen, row, col,
             {{" " + plain, kTitle}, {marked ? stale : "", kStaleMark}, {" ", kTitle}}, limit);
}

// ┌ title ───┐ ... └──┘ around `box`.
void draw_frame(Screen& screen, const Box& box, const std::string& title) {
    const int right = box.col + box.width - 1;
    const int bottom = box.row + box.height - 1;
    for (int x = box.col + 1; x < right; ++x) {
        screen.set(box.row, x, "─", kBorder);
        screen.set(bottom, x, "─", kBorder);
    }
    for (int y = box.row + 1; y < bottom; ++y) {
        screen.set(y, box.col, "│", kBorder);
        screen.set(y, right, "│", kBorder);
    }
    screen.set(box.row, box.col, "┌", kBorder);
    screen.set(box.row, right, "┐", kBorder);
    screen.set(bottom, box.col, "└", kBorder);
    screen.set(bottom, right, "┘", kBorder);
    put_title(screen, box.row, box.col + 2, title, box.width - 4);
}

// ├ title ───┤ across the box at `row`.
void draw_divider(Screen& screen, const Box& box, int row, const std::string& title) {
    for (int x = box.col + 1; x < box.col + box.width - 1; ++x) {
        screen.set(row, x, "─", kBorder);
    }
    screen.set(row, box.col, "├", kBorder);
    screen.set(row, box.col + box.width - 1, "┤", kBorder);
    put_title(screen, row, box.col + 2, title, box.width - 4);
}

// Left panel: horizon, roll/pitch line, heading tape.
void draw_attitude_panel(Screen& screen, const Box& box, const MonitorModel& model, bool ascii) {
    draw_frame(screen, box, section_title(model, "Attitude (IMU)"));
    const Box inner{box.row + 1, box.col + 1, box.width - 2, box.height - 2};
    if (!model.attitude) {
        screen.put(inner.row + inner.height / 2, inner.col + 1, "waiting for attitude", kLabel,
                   inner.width - 2);
        return;
    }
    const auto& imu = model.attitude->imu;
    const Box horizon{inner.row, inner.col, inner.width, inner.height - 3};
    draw_horizon(screen, horizon, imu.roll, imu.pitch, ascii);
    const int text_row = horizon.row + horizon.height;
    put_line(screen, text_row, inner.col,
             {{" roll ", kLabel},
              {signed_value(imu.roll, 1, "°"), kValue},
              {"  pitch ", kLabel},
              {signed_value(imu.pitch, 1, "°"), kValue}},
             inner.width);
    draw_heading_tape(screen, Box{text_row + 1, inner.col, inner.width, 2}, imu.yaw);
}

// Right panel: sections of lines with dividers between them.
void draw_info_panel(Screen& screen, const Box& box, const MonitorModel& model) {
    const std::vector<std::pair<std::string, std::vector<Line>>> sections = {
        {"Angles", angle_table(model)},
        {"Motion", motion_lines(model)},
        {"Daemon", daemon_lines(model)},
    };
    draw_frame(screen, box, section_title(model, sections.front().first));
    const int bottom = box.row + box.height - 1;
    int row = box.row + 1;
    for (std::size_t i = 0; i < sections.size() && row < bottom; ++i) {
        if (i > 0) {
            draw_divider(screen, box, row++, section_title(model, sections[i].first));
        }
        for (const auto& line : sections[i].second) {
            if (row >= bottom) {
                break;
            }
            put_line(screen, row++, box.col + 2, line, box.width - 3);
        }
    }
}

// The event list from `row` to `last_row` (inclusive), under a title rule.
void draw_events(Screen& screen, int row, int last_row, const MonitorModel& model) {
    if (row > last_row) {
        return;
    }
    for (int x = 0; x < screen.width(); ++x) {
        screen.set(row, x, "─", kBorder);
    }
    screen.put(row, 2, " Events ", kTitle);
    const int room = last_row - row;
    const auto& events = model.events;
    const auto first = events.size() > static_cast<std::size_t>(room)
                           ? events.size() - static_cast<std::size_t>(room)
                           : 0;
    for (std::size_t i = first; i < events.size(); ++i) {
        put_line(screen, ++row, 1, event_line(events[i]), screen.width() - 2);
    }
}

// The two columns from row `top`, the events under them.
void render_wide(Screen& screen, const MonitorModel& model, int top, bool ascii) {
    const int width = screen.width();
    const int height = screen.height();
    constexpr int kPanelRows = 15;  // what the info panel needs
    const int events_rows = std::clamp(height - top - 1 - kPanelRows, 3, 9);
    const int body_rows = height - top - 1 - events_rows;
    const int left_width = std::clamp(width * 2 / 5 + 2, 30, 48);
    draw_attitude_panel(screen, Box{top, 0, left_width, body_rows}, model, ascii);
    draw_info_panel(screen, Box{top, left_width, width - left_width, body_rows}, model);
    if (!model.connected) {
        dim_rows(screen, top, top + body_rows);
    }
    draw_events(screen, top + body_rows, height - 2, model);
}

// One column from row `top`: angles, motion, daemon, then the events.
void render_narrow(Screen& screen, const MonitorModel& model, int top) {
    std::vector<Line> lines;
    if (!model.connected) {
        lines.push_back({{"stale", kStaleMark}, {"   last known values:", kLabel}});
    }
    for (auto& part : {angle_lines_compact(model), motion_lines(model), daemon_lines(model)}) {
        lines.insert(lines.end(), part.begin(), part.end());
    }
    const int last = screen.height() - 2;  // the row above the keys
    int row = top;
    for (const auto& line : lines) {
        if (row > last) {
            break;
        }
        put_line(screen, row++, 1, line, screen.width() - 1);
    }
    if (!model.connected) {
        dim_rows(screen, top, row);
    }
    draw_events(screen, row, last, model);
}

// The link line; without gportd, the reason whole under it. The next free row.
int draw_link(Screen& screen, const MonitorModel& model) {
    const int width = screen.width();
    put_line(screen, 1, 1, link_line(model), width - 1);
    if (model.connected) {
        return 2;
    }
    constexpr int kMaxReasonRows = 4;
    int row = 2;
    for (const auto& line : reason_lines(model, width - 2, kMaxReasonRows)) {
        put_line(screen, row++, 1, line, width - 1);
    }
    return row;
}

}  // namespace

Screen render(const MonitorModel& model, int width, int height, Charset charset) {
    Screen screen(width, height);
    if (width < kMinWidth || height < kMinHeight) {
        const std::string text = fmt::format("too small: {}x{}", width, height);
        screen.put(height / 2, std::max((width - columns(text)) / 2, 0), text);
        return screen;
    }
    const bool ascii = charset == Charset::kAscii;
    draw_header(screen, model, ascii);
    const int top = draw_link(screen, model);
    if (width >= kWideMinWidth && height >= kWideMinHeight) {
        render_wide(screen, model, top, ascii);
    } else {
        render_narrow(screen, model, top);
    }
    put_line(screen, height - 1, 1, key_line(model), width - 1);
    if (ascii) {
        to_ascii(screen);
    }
    return screen;
}

std::string render_plain(const MonitorModel& model, std::size_t new_events, Charset charset) {
    std::string out = fmt::format("gportctl monitor {} · {}", model.clock, model.socket);
    if (!model.daemon_version.empty()) {
        out += " · gportd " + model.daemon_version;
    }
    out += fmt::format("\n{}\n", line_text(link_line(model)));
    if (!model.connected) {
        out += fmt::format("reason  {}\nstale   the values below are from before {}\n",
                           model.connection_error, model.stale_since);
    }
    std::vector<Line> lines = angle_table(model);
    for (auto& part : {motion_lines(model), daemon_lines(model)}) {
        lines.insert(lines.end(), part.begin(), part.end());
    }
    for (const auto& line : lines) {
        std::string text = line_text(line);
        text.erase(text.find_last_not_of(' ') + 1);
        out += fmt::format("{}\n", text);
    }
    const auto& events = model.events;
    const auto shown = std::min(new_events, events.size());
    for (std::size_t i = events.size() - shown; i < events.size(); ++i) {
        out += fmt::format("event  {}\n", line_text(event_line(events[i])));
    }
    out += "\n";
    return charset == Charset::kAscii ? to_ascii(out) : out;
}

}  // namespace gport::cli::monitor
