#include "lines.hpp"

#include <fmt/format.h>

#include "render.hpp"
#include "text.hpp"

namespace gport::cli::monitor {
namespace {

std::string cell(double value, const char* unit) {
    return fmt::format("{:>9}", signed_value(value, 2, unit));
}

Line axes_row(const char* label, const client::Axes& axes, const char* unit) {
    return {{fmt::format("{:<6}", label), kLabel},
            {cell(axes.roll, unit) + cell(axes.pitch, unit) + cell(axes.yaw, unit), kValue}};
}

std::string compact(const client::Axes& a, const char* unit) {
    return fmt::format("r {} p {} y {} {}", signed_value(a.roll, 1, ""),
                       signed_value(a.pitch, 1, ""), signed_value(a.yaw, 1, ""), unit);
}

Line labelled(const std::string& label, const std::string& value, Style style = kValue) {
    return {{fmt::format("{:<8}", label), kLabel}, {value, style}};
}

std::string age_text(const MonitorModel& model) {
    if (!model.attitude_age_ms) {
        return "no sample yet";
    }
    const auto ms = *model.attitude_age_ms;
    return ms < 1000 ? fmt::format("last sample {} ms ago", ms)
                     : "last sample " + duration_text(ms) + " ago";
}

}  // namespace

Style severity_style(Severity severity) {
    switch (severity) {
        case Severity::kGood:
            return Style{.fg = Color::kGreen};
        case Severity::kWarn:
            return Style{.fg = Color::kYellow};
        case Severity::kBad:
            return Style{.fg = Color::kRed, .bold = true};
        case Severity::kInfo:
            break;
    }
    return kValue;
}

Style link_style(const std::string& state) {
    if (state == "up") {
        return Style{.fg = Color::kGreen, .bold = true};
    }
    if (state == "stale") {
        return Style{.fg = Color::kYellow, .bold = true};
    }
    if (state == "down") {
        return Style{.fg = Color::kRed, .bold = true};
    }
    return Style{.fg = Color::kGrey, .bold = true};
}

std::vector<Line> angle_table(const MonitorModel& model) {
    std::vector<Line> lines;
    lines.push_back({{fmt::format("{:<6}{:>9}{:>9}{:>9}", "", "roll", "pitch", "yaw"), kLabel}});
    if (!model.attitude) {
        lines.push_back(labelled("", "no attitude yet", kLabel));
        return lines;
    }
    const auto& a = *model.attitude;
    lines.push_back(axes_row("IMU", a.imu, "°"));
    lines.push_back(axes_row("hall", a.hall, "°"));
    if (a.rates) {
        lines.push_back(axes_row("rate", a.rates->hall, " "));  // digits under the angles
        lines.back().push_back({"°/s", kLabel});
        lines.push_back(labelled(
            "IMU ω",
            fmt::format("x {} y {} z {} °/s", signed_value(a.rates->imu.x, 1, ""),
                        signed_value(a.rates->imu.y, 1, ""), signed_value(a.rates->imu.z, 1, ""))));
    } else {
        lines.push_back(labelled("rates", "not sent by this gimbal", kLabel));
    }
    return lines;
}

std::vector<Line> angle_lines_compact(const MonitorModel& model) {
    if (!model.attitude) {
        return {labelled("IMU", "no attitude yet", kLabel)};
    }
    const auto& a = *model.attitude;
    std::vector<Line> lines = {labelled("IMU", compact(a.imu, "°")),
                               labelled("hall", compact(a.hall, "°"))};
    if (a.rates) {
        lines.push_back(labelled("rates", compact(a.rates->hall, "°/s")));
    }
    return lines;
}

std::vector<Line> motion_lines(const MonitorModel& model) {
    std::vector<Line> lines;
    if (!model.motion) {
        lines.push_back(labelled("motion", "none", kLabel));
        lines.push_back(labelled("", ""));
    } else {
        const auto& m = *model.motion;
        std::string what = m.speed    ? axes_text(*m.speed, "°/s")
                           : m.target ? "to " + axes_text(*m.target, "°")
                                      : "";
        lines.push_back(labelled(m.mode, what, Style{.fg = Color::kGreen, .bold = true}));
        std::string when;
        if (m.time_left_ms) {
            when = duration_text(*m.time_left_ms) + " left";
        } else if (m.elapsed_ms) {
            when = duration_text(*m.elapsed_ms) + " so far";
        }
        lines.push_back(labelled("owner", m.owner + (when.empty() ? "" : " · " + when)));
    }
    if (model.last_end) {
        const auto& end = *model.last_end;
        lines.push_back(
            labelled("ended", fmt::format("{}: {} at {}", end.mode, end.reason, end.clock)));
    } else {
        lines.push_back(labelled("ended", "-", kLabel));
    }
    return lines;
}

std::vector<Line> daemon_lines(const MonitorModel& model) {
    std::vector<Line> lines;
    std::string control = model.controller;
    if (control == "free") {
        control += " (last command wins)";
    }
    lines.push_back(
        labelled("control", control, model.holds_control ? Style{.fg = Color::kGreen} : kValue));
    if (!model.counters) {
        lines.push_back(labelled("frames", "-", kLabel));
        lines.push_back(labelled("drops", "-", kLabel));
        return lines;
    }
    const auto& c = *model.counters;
    std::string frames = fmt::format("{}", c.attitude_frames);
    if (model.frame_rate_hz) {
        frames += fmt::format(" ({:.0f}/s)", *model.frame_rate_hz);
    }
    lines.push_back(
        {{fmt::format("{:<8}", "frames"), kLabel},
         {frames, kValue},
         {"  crc ", kLabel},
         {fmt::format("{}", c.crc_errors), c.crc_errors > 0 ? Style{.fg = Color::kYellow} : kValue},
         {"  resync ", kLabel},
         {fmt::format("{}", c.resyncs), kValue}});
    lines.push_back({{fmt::format("{:<8}", "drops"), kLabel},
                     {fmt::format("{} (you {})", model.dropped_total, model.dropped_self), kValue},
                     {"  clients ", kLabel},
                     {fmt::format("{}", model.clients), kValue},
                     {"  rec ", kLabel},
                     {model.recording, kValue}});
    return lines;
}

Line link_line(const MonitorModel& model) {
    if (!model.connected) {
        return {{"daemon ", kLabel},
                {"✖ NOT CONNECTED", Style{.fg = Color::kRed, .bold = true}},
                {(model.stale_since.empty() ? "" : "  since " + model.stale_since) +
                     " · retrying every second",
                 kValue}};
    }
    std::string state = model.link_state;
    for (auto& c : state) {
        c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    }
    Line line = {{"link ", kLabel}, {"● " + state, link_style(model.link_state)}};
    if (!model.link_reason.empty()) {
        line.push_back({"  " + model.link_reason, kValue});
    }
    line.push_back({" · " + age_text(model), kValue});
    if (!model.device.empty()) {
        line.push_back({" · " + model.device + (model.device_open ? "" : " (not open)"), kLabel});
    }
    return line;
}

std::vector<Line> reason_lines(const MonitorModel& model, int width, int max_rows) {
    constexpr int kIndent = 8;  // under the value column of "reason  "
    auto rows = wrap(model.connection_error, std::max(width - kIndent, 1));
    if (static_cast<int>(rows.size()) > max_rows && max_rows > 0) {
        rows.resize(static_cast<std::size_t>(max_rows));
        rows.back() = fit(rows.back(), std::max(width - kIndent - 1, 0)) + "…";
    }
    std::vector<Line> lines;
    for (std::size_t i = 0; i < rows.size() && static_cast<int>(i) < max_rows; ++i) {
        lines.push_back(labelled(i == 0 ? "reason" : "", rows[i]));
    }
    return lines;
}

Line key_line(const MonitorModel& model) {
    const Style key{.bold = true};
    Line line = {{"q", key}, {" quit  ", kLabel}, {"c", key}, {" centre  ", kLabel}};
    if (!model.control_requested) {
        line.push_back({"arrows nudge with --control", kLabel});
        return line;
    }
    line.push_back({"←→", key});
    line.push_back({" yaw  ", kLabel});
    line.push_back({"↑↓", key});
    line.push_back({fmt::format(" pitch ({:.0f} °/s)  ", kNudgeSpeedDegPerS), kLabel});
    line.push_back(model.holds_control ? Span{"control: you", Style{.fg = Color::kGreen}}
                                       : Span{"control: not held", Style{.fg = Color::kYellow}});
    return line;
}

Line event_line(const EventLine& event) {
    return {{event.clock + "  ", kLabel}, {event.text, severity_style(event.severity)}};
}

int put_line(Screen& screen, int row, int col, const Line& line, int width) {
    int used = 0;
    for (const auto& span : line) {
        if (used >= width) {
            break;
        }
        used += screen.put(row, col + used, span.text, span.style, width - used);
    }
    return used;
}

std::string line_text(const Line& line) {
    std::string text;
    for (const auto& span : line) {
        text += span.text;
    }
    return text;
}

}  // namespace gport::cli::monitor
