// One hexadecimal digit's value (0-15), or -1 for any other character. Used
// by gport-sim's recordings and gport-mavlink's signing key file.
#pragma once

namespace gport::base {

constexpr int hex_digit(char c) {
    if (c >= '0' && c <= '9') {
        return c - '0';
    }
    if (c >= 'a' && c <= 'f') {
        return c - 'a' + 10;
    }
    if (c >= 'A' && c <= 'F') {
        return c - 'A' + 10;
    }
    return -1;
}

static_assert(hex_digit('0') == 0 && hex_digit('f') == 15 && hex_digit('F') == 15);
static_assert(hex_digit('g') == -1 && hex_digit(' ') == -1);

}  // namespace gport::base
