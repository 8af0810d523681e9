// A frame of text for the monitor: a grid of one-column cells, each a UTF-8
// glyph with a style. The renderer draws into it (pure, no terminal); the
// terminal side turns it into ANSI output, only the rows that changed since
// the previous frame, or into plain lines.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace gport::cli::monitor {

enum class Color : std::uint8_t { kDefault, kRed, kGreen, kYellow, kBlue, kMagenta, kCyan, kGrey };

struct Style {
    Color fg = Color::kDefault;
    bool bold = false;
    bool reverse = false;
    bool dim = false;  // faint: values that are no longer live
    friend bool operator==(const Style&, const Style&) = default;
};

struct Cell {
    std::string glyph = " ";  // one column wide
    Style style{};
    friend bool operator==(const Cell&, const Cell&) = default;
};

// Code points of a UTF-8 string, each re-encoded on its own: every glyph the
// monitor draws is one column wide (ASCII, Latin-1, box drawing, braille,
// arrows), so a code point is a column.
std::vector<std::string> split_glyphs(std::string_view text);
// Columns `text` takes (its code points).
int columns(std::string_view text);

class Screen {
  public:
    Screen(int width, int height);

    int width() const { return width_; }
    int height() const { return height_; }

    // Writes text from (row, col) to the right, clipped at `limit` columns
    // from col (and at the screen's edge); returns the columns written.
    int put(int row, int col, std::string_view text, Style style = {}, int limit = -1);
    void set(int row, int col, std::string glyph, Style style = {});
    const Cell& at(int row, int col) const;

    // A row's glyphs without styles, trailing spaces trimmed.
    std::string row_text(int row) const;
    // Every row's text, '\n' after each; trailing empty rows kept.
    std::string text() const;

    friend bool operator==(const Screen&, const Screen&) = default;

  private:
    int width_;
    int height_;
    std::vector<Cell> cells_;
};

// The ANSI bytes that turn the terminal showing `previous` (nullptr: an
// unknown screen, e.g. the first frame or after a resize) into `next`:
// cursor moves and whole changed rows, with SGR colours only when `color`.
std::string ansi_update(const Screen* previous, const Screen& next, bool color);

}  // namespace gport::cli::monitor
