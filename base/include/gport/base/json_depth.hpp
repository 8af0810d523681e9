// How deep arrays and objects nest in a JSON text, counted with one flat
// pass before the text reaches nlohmann's parser, which recurses once per
// level: gportd's request reader and libgport-client's line reader refuse a
// line nested deeper than their limit, so no input can exhaust the stack.
#pragma once

#include <cstddef>
#include <string_view>

namespace gport::base {

// True when arrays and objects nest deeper than `limit` in `text`. Brackets
// inside strings do not count (an escaped quote does not end a string); a
// closing bracket with nothing open is ignored (the parser rejects it).
constexpr bool nested_deeper_than(std::string_view text, std::size_t limit) noexcept {
    std::size_t depth = 0;
    bool in_string = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (in_string) {
            if (c == '\\') {
                ++i;  // the escaped character, a quote included
            } else if (c == '"') {
                in_string = false;
            }
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > limit) {
                return true;
            }
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        }
    }
    return false;
}

}  // namespace gport::base
