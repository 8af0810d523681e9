#include "charset.hpp"

#include <langinfo.h>
#include <locale.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdlib>
#include <utility>

namespace gport::cli::monitor {
namespace {

// The locale name that decides LC_CTYPE, as setlocale(LC_CTYPE, "") reads it.
std::string ctype_locale_name() {
    for (const char* name : {"LC_ALL", "LC_CTYPE", "LANG"}) {
        const char* value = std::getenv(name);
        if (value != nullptr && *value != '\0') {
            return value;
        }
    }
    return "C";
}

bool names_utf8(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    text.erase(std::remove(text.begin(), text.end(), '-'), text.end());
    return text.find("utf8") != std::string::npos;
}

constexpr std::array<std::pair<std::string_view, std::string_view>, 28> kAscii = {{
    {"─", "-"}, {"━", "="}, {"│", "|"}, {"┌", "+"}, {"┐", "+"}, {"└", "+"}, {"┘", "+"},
    {"├", "+"}, {"┤", "+"}, {"┬", "+"}, {"┴", "+"}, {"┼", "+"}, {"╋", "+"}, {"●", "*"},
    {"✖", "X"}, {"▲", "^"}, {"°", "d"}, {"·", "-"}, {"…", "~"}, {"←", "<"}, {"→", ">"},
    {"↑", "^"}, {"↓", "v"}, {"ω", "w"}, {"×", "x"}, {"–", "-"}, {"—", "-"}, {"’", "'"},
}};

}  // namespace

Charset charset_from_locale() {
    const locale_t locale = ::newlocale(LC_CTYPE_MASK, "", static_cast<locale_t>(nullptr));
    if (locale == static_cast<locale_t>(nullptr)) {
        return names_utf8(ctype_locale_name()) ? Charset::kUtf8 : Charset::kAscii;
    }
    const bool utf8 = names_utf8(::nl_langinfo_l(CODESET, locale));
    ::freelocale(locale);
    return utf8 ? Charset::kUtf8 : Charset::kAscii;
}

std::string_view ascii_glyph(std::string_view glyph) {
    if (glyph.size() == 1 && static_cast<unsigned char>(glyph[0]) < 0x80) {
        return glyph;
    }
    for (const auto& [from, to] : kAscii) {
        if (glyph == from) {
            return to;
        }
    }
    return "?";
}

std::string to_ascii(std::string_view text) {
    std::string out;
    for (const auto& glyph : split_glyphs(text)) {
        out += ascii_glyph(glyph);
    }
    return out;
}

void to_ascii(Screen& screen) {
    for (int row = 0; row < screen.height(); ++row) {
        for (int col = 0; col < screen.width(); ++col) {
            const Cell& cell = screen.at(row, col);
            screen.set(row, col, std::string(ascii_glyph(cell.glyph)), cell.style);
        }
    }
}

}  // namespace gport::cli::monitor
