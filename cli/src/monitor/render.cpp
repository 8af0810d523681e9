#include "render.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "attitude_view.hpp"
#include "lines.hpp"
#include "text.hpp"

namespace gport::cli::monitor {
namespace {

constexpr Style kHeader{.bold = true, .reverse = true};
constexpr Style kBorder{.fg = Color::kGrey};

// The title bar: program, daemon, socket on the left; uptime and clock right.
void draw_header(Screen& screen, const MonitorModel& model) {
    const int width = screen.width();
    screen.put(0, 0, std::string(static_cast<std::size_t>(width), ' '), kHeader);
    const std::string left = fmt::format(
        " gportctl monitor{} · {}",
        model.daemon_version.empty() ? "" : " · gportd " + model.daemon_version, model.socket);
    const std::string right =
        model.uptime_ms ? fmt::format("up {}  {} ", duration_text(*model.uptime_ms), model.clock)
                        : fmt::format("{} ", model.clock);
    const int right_cols = columns(right);
    const int room = std::max(width - right_cols - 1, 0);
    screen.put(0, 0, left, kHeader, room);
    if (width - right_cols > columns(left)) {
        screen.put(0, width - right_cols, right, kHeader);
    }
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
    screen.put(box.row, box.col + 2, fmt::format(" {} ", title), kTitle, box.width - 4);
}

// ├ title ───┤ across the box at `row`.
void draw_divider(Screen& screen, const Box& box, int row, const std::string& title) {
    for (int x = box.col + 1; x < box.col + box.width - 1; ++x) {
        screen.set(row, x, "─", kBorder);
    }
    screen.set(row, box.col, "├", kBorder);
    screen.set(row, box.col + box.width - 1, "┤", kBorder);
    screen.put(row, box.col + 2, fmt::format(" {} ", title), kTitle, box.width - 4);
}

// Left panel: horizon, roll/pitch line, heading tape.
void draw_attitude_panel(Screen& screen, const Box& box, const MonitorModel& model) {
    draw_frame(screen, box, "Attitude (IMU)");
    const Box inner{box.row + 1, box.col + 1, box.width - 2, box.height - 2};
    if (!model.attitude) {
        screen.put(inner.row + inner.height / 2, inner.col + 1, "waiting for attitude", kLabel,
                   inner.width - 2);
        return;
    }
    const auto& imu = model.attitude->imu;
    const Box horizon{inner.row, inner.col, inner.width, inner.height - 3};
    draw_horizon(screen, horizon, imu.roll, imu.pitch);
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
    draw_frame(screen, box, sections.front().first);
    const int bottom = box.row + box.height - 1;
    int row = box.row + 1;
    for (std::size_t i = 0; i < sections.size() && row < bottom; ++i) {
        if (i > 0) {
            draw_divider(screen, box, row++, sections[i].first);
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

void render_wide(Screen& screen, const MonitorModel& model) {
    const int width = screen.width();
    const int height = screen.height();
    constexpr int kPanelRows = 15;  // what the info panel needs
    const int events_rows = std::clamp(height - 3 - kPanelRows, 3, 9);
    const int body_rows = height - 3 - events_rows;
    const int left_width = std::clamp(width * 2 / 5 + 2, 30, 48);
    draw_attitude_panel(screen, Box{2, 0, left_width, body_rows}, model);
    draw_info_panel(screen, Box{2, left_width, width - left_width, body_rows}, model);
    draw_events(screen, 2 + body_rows, height - 2, model);
}

void render_narrow(Screen& screen, const MonitorModel& model) {
    std::vector<Line> lines = angle_lines_compact(model);
    for (auto& part : {motion_lines(model), daemon_lines(model)}) {
        lines.insert(lines.end(), part.begin(), part.end());
    }
    const int last = screen.height() - 2;  // the row above the keys
    int row = 2;
    for (const auto& line : lines) {
        if (row > last) {
            return;
        }
        put_line(screen, row++, 1, line, screen.width() - 1);
    }
    draw_events(screen, row, last, model);
}

}  // namespace

Screen render(const MonitorModel& model, int width, int height) {
    Screen screen(width, height);
    if (width < kMinWidth || height < kMinHeight) {
        const std::string text = fmt::format("too small: {}x{}", width, height);
        screen.put(height / 2, std::max((width - columns(text)) / 2, 0), text);
        return screen;
    }
    draw_header(screen, model);
    put_line(screen, 1, 1, link_line(model), width - 1);
    if (width >= kWideMinWidth && height >= kWideMinHeight) {
        render_wide(screen, model);
    } else {
        render_narrow(screen, model);
    }
    put_line(screen, height - 1, 1, key_line(model), width - 1);
    return screen;
}

std::string render_plain(const MonitorModel& model, std::size_t new_events) {
    std::string out = fmt::format("gportctl monitor {} · {}", model.clock, model.socket);
    if (!model.daemon_version.empty()) {
        out += " · gportd " + model.daemon_version;
    }
    out += fmt::format("\n{}\n", line_text(link_line(model)));
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
    return out;
}

}  // namespace gport::cli::monitor
