// printable (printable.hpp): text from others, safe for a terminal.
#include "gport/client/printable.hpp"

#include <cstdio>

namespace gport::client {
namespace {

// Length of the well-formed UTF-8 sequence at the start of `text` (RFC 3629,
// table 3-7 of the Unicode standard); 0 when it is not one.
std::size_t sequence_at(std::string_view text) {
    const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
    const unsigned char lead = byte(0);
    std::size_t length = 0;
    unsigned char low = 0x80;
    unsigned char high = 0xBF;
    if (lead >= 0xC2 && lead <= 0xDF) {
        length = 2;
    } else if (lead >= 0xE0 && lead <= 0xEF) {
        length = 3;
        low = lead == 0xE0 ? 0xA0 : 0x80;   // no overlong forms
        high = lead == 0xED ? 0x9F : 0xBF;  // no surrogates
    } else if (lead >= 0xF0 && lead <= 0xF4) {
        length = 4;
        low = lead == 0xF0 ? 0x90 : 0x80;
        high = lead == 0xF4 ? 0x8F : 0xBF;  // nothing past U+10FFFF
    } else {
        return 0;
    }
    if (text.size() < length || byte(1) < low || byte(1) > high) {
        return 0;
    }
    for (std::size_t i = 2; i < length; ++i) {
        if (byte(i) < 0x80 || byte(i) > 0xBF) {
            return 0;
        }
    }
    return length;
}

bool is_c1(std::string_view sequence) {
    return sequence.size() == 2 && static_cast<unsigned char>(sequence[0]) == 0xC2 &&
           static_cast<unsigned char>(sequence[1]) <= 0x9F;
}

// "\x1b" or "\u009b".
std::string escaped(const char* format, unsigned char code) {
    char text[8];
    std::snprintf(text, sizeof(text), format, static_cast<unsigned>(code));
    return text;
}

}  // namespace

std::string printable(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    std::size_t i = 0;
    while (i < text.size()) {
        const auto c = static_cast<unsigned char>(text[i]);
        const auto length = c < 0x80 ? 1 : sequence_at(text.substr(i));
        if (c < 0x20 || c == 0x7F || length == 0) {
            out += escaped("\\x%02x", c);
            ++i;
            continue;
        }
        const auto sequence = text.substr(i, length);
        out += is_c1(sequence) ? escaped("\\u%04x", static_cast<unsigned char>(sequence[1]))
                               : std::string(sequence);
        i += length;
    }
    return out;
}

}  // namespace gport::client
