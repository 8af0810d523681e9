#include "screen.hpp"

#include <fmt/format.h>

#include <stdexcept>

namespace gport::cli::monitor {
namespace {

// Bytes in the UTF-8 sequence that starts with `lead` (1 for a stray byte).
std::size_t sequence_length(unsigned char lead) {
    if (lead >= 0xF0 && lead < 0xF8) {
        return 4;
    }
    if (lead >= 0xE0) {
        return lead < 0xF0 ? 3 : 1;
    }
    if (lead >= 0xC0) {
        return 2;
    }
    return 1;
}

int sgr_colour(Color color) {
    switch (color) {
        case Color::kRed:
            return 31;
        case Color::kGreen:
            return 32;
        case Color::kYellow:
            return 33;
        case Color::kBlue:
            return 34;
        case Color::kMagenta:
            return 35;
        case Color::kCyan:
            return 36;
        case Color::kGrey:
            return 90;
        case Color::kDefault:
            break;
    }
    return 39;
}

std::string sgr(const Style& style) {
    return fmt::format("\x1b[0;{}{}{}{}m", sgr_colour(style.fg), style.bold ? ";1" : "",
                       style.dim ? ";2" : "", style.reverse ? ";7" : "");
}

void append_row(std::string& out, const Screen& screen, int row, bool color) {
    out += fmt::format("\x1b[{};1H", row + 1);
    Style current{};
    if (color) {
        out += "\x1b[0m";
    }
    for (int col = 0; col < screen.width(); ++col) {
        const Cell& cell = screen.at(row, col);
        if (color && cell.style != current) {
            out += sgr(cell.style);
            current = cell.style;
        }
        out += cell.glyph;
    }
    if (color && current != Style{}) {
        out += "\x1b[0m";
    }
}

bool same_row(const Screen& a, const Screen& b, int row) {
    for (int col = 0; col < a.width(); ++col) {
        if (!(a.at(row, col) == b.at(row, col))) {
            return false;
        }
    }
    return true;
}

}  // namespace

std::vector<std::string> split_glyphs(std::string_view text) {
    std::vector<std::string> glyphs;
    std::size_t i = 0;
    while (i < text.size()) {
        std::size_t n = sequence_length(static_cast<unsigned char>(text[i]));
        n = std::min(n, text.size() - i);
        glyphs.emplace_back(text.substr(i, n));
        i += n;
    }
    return glyphs;
}

int columns(std::string_view text) {
    int count = 0;
    for (unsigned char c : text) {
        count += (c & 0xC0) != 0x80 ? 1 : 0;
    }
    return count;
}

Screen::Screen(int width, int height)
    : width_(std::max(width, 0)),
      height_(std::max(height, 0)),
      cells_(static_cast<std::size_t>(width_ * height_)) {}

int Screen::put(int row, int col, std::string_view text, Style style, int limit) {
    if (row < 0 || row >= height_) {
        return 0;
    }
    const int end = limit < 0 ? width_ : std::min(width_, col + limit);
    int written = 0;
    for (auto& glyph : split_glyphs(text)) {
        const int c = col + written;
        if (c >= end) {
            break;
        }
        if (c >= 0) {
            set(row, c, std::move(glyph), style);
        }
        ++written;
    }
    return written;
}

void Screen::set(int row, int col, std::string glyph, Style style) {
    if (row < 0 || row >= height_ || col < 0 || col >= width_) {
        return;
    }
    auto& cell = cells_[static_cast<std::size_t>(row * width_ + col)];
    cell.glyph = std::move(glyph);
    cell.style = style;
}

const Cell& Screen::at(int row, int col) const {
    if (row < 0 || row >= height_ || col < 0 || col >= width_) {
        throw std::out_of_range(fmt::format("cell {},{} outside {}x{}", row, col, width_, height_));
    }
    return cells_[static_cast<std::size_t>(row * width_ + col)];
}

std::string Screen::row_text(int row) const {
    std::string line;
    for (int col = 0; col < width_; ++col) {
        line += at(row, col).glyph;
    }
    const auto end = line.find_last_not_of(' ');
    line.resize(end == std::string::npos ? 0 : end + 1);
    return line;
}

std::string Screen::text() const {
    std::string all;
    for (int row = 0; row < height_; ++row) {
        all += row_text(row) + "\n";
    }
    return all;
}

std::string ansi_update(const Screen* previous, const Screen& next, bool color) {
    const bool full = previous == nullptr || previous->width() != next.width() ||
                      previous->height() != next.height();
    std::string out = full ? std::string(color ? "\x1b[0m" : "") + "\x1b[H\x1b[2J" : "";
    for (int row = 0; row < next.height(); ++row) {
        if (full || !same_row(*previous, next, row)) {
            append_row(out, next, row, color);
        }
    }
    return out;
}

}  // namespace gport::cli::monitor
