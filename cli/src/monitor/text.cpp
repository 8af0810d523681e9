#include "text.hpp"

#include <fmt/format.h>

#include <cmath>
#include <vector>

#include "screen.hpp"

namespace gport::cli::monitor {

std::string signed_value(double value, int decimals, const char* unit) {
    // -0.00 prints as +0.00: the sign of a rounded zero means nothing.
    const double scale = std::pow(10.0, decimals);
    if (std::round(value * scale) == 0) {
        value = 0;
    }
    return fmt::format("{:+.{}f}{}", value, decimals, unit);
}

std::string axes_text(const client::Axes& axes, const char* unit) {
    const std::vector<std::pair<const char*, double>> parts = {
        {"roll", axes.roll}, {"pitch", axes.pitch}, {"yaw", axes.yaw}};
    std::string out;
    for (const auto& [name, value] : parts) {
        if (value != 0) {
            out += fmt::format("{}{} {}", out.empty() ? "" : " ", name, signed_value(value, 1, ""));
        }
    }
    return (out.empty() ? std::string("0") : out) + " " + unit;
}

std::string peer_text(const std::optional<client::Peer>& peer, std::int64_t self_id) {
    if (!peer) {
        return "nobody";
    }
    if (peer->id == self_id && self_id != 0) {
        return "you";
    }
    return fmt::format("pid {} (client {})", peer->pid, peer->id);
}

std::string duration_text(std::int64_t ms) {
    ms = std::max<std::int64_t>(ms, 0);
    const std::int64_t s = ms / 1000;
    if (s >= 3600) {
        return fmt::format("{}h {:02}m", s / 3600, s / 60 % 60);
    }
    if (s >= 60) {
        return fmt::format("{}m {:02}s", s / 60, s % 60);
    }
    if (s >= 10) {
        return fmt::format("{} s", s);
    }
    return fmt::format("{:.1f} s", static_cast<double>(ms) / 1000.0);
}

std::vector<std::string> wrap(const std::string& text, int width) {
    std::vector<std::string> rows;
    if (width <= 0) {
        return rows;
    }
    std::string row;
    int used = 0;
    for (const auto& glyph : split_glyphs(text)) {
        if (used == width) {  // break at the last space, else right here
            const auto space = row.find_last_of(' ');
            std::string rest;
            if (glyph != " " && space != std::string::npos && space > 0) {
                rest = row.substr(space + 1);
                row.resize(space);
            }
            rows.push_back(row);
            row = rest;
            used = columns(row);
            if (glyph == " ") {
                continue;
            }
        }
        if (!(used == 0 && glyph == " " && !rows.empty())) {
            row += glyph;
            ++used;
        }
    }
    if (!row.empty() || rows.empty()) {
        rows.push_back(row);
    }
    return rows;
}

std::string fit(const std::string& text, int width) {
    std::string out;
    int used = 0;
    for (const auto& glyph : split_glyphs(text)) {
        if (used == width) {
            break;
        }
        out += glyph;
        ++used;
    }
    return out + std::string(static_cast<std::size_t>(std::max(width - used, 0)), ' ');
}

}  // namespace gport::cli::monitor
