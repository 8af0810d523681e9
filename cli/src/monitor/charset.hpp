// The characters the monitor may use: UTF-8 (box drawing, braille, °, ●,
// arrows) when the locale's character set is UTF-8, else plain ASCII
// (docs/monitor.md, "Characters").
#pragma once

#include <string>
#include <string_view>

#include "screen.hpp"

namespace gport::cli::monitor {

enum class Charset { kUtf8, kAscii };

// From the locale in the environment (LC_ALL, LC_CTYPE, LANG):
// nl_langinfo(CODESET) is "UTF-8", else ASCII. A locale that is not
// installed counts by its name ("…UTF-8"/"…utf8"), as the terminal set up
// for it most likely speaks UTF-8 even though the C library cannot load it.
Charset charset_from_locale();

// One glyph in ASCII: box drawing as - | +, ● *, ▲ ^, ° d, arrows < > ^ v,
// anything else that is not ASCII as ?.
std::string_view ascii_glyph(std::string_view glyph);
// Every glyph of `text` through ascii_glyph (the same number of columns).
std::string to_ascii(std::string_view text);
// Every cell of `screen` through ascii_glyph.
void to_ascii(Screen& screen);

}  // namespace gport::cli::monitor
