// A minimal valid baseline JPEG, 8x8 grey, for the tests that tag images
// with exiftool (gportctl geotag: tests/cli, tests/integration).
#pragma once

#include <string>

namespace gport::testing {

// SOI, JFIF, a quantisation table of ones, an 8x8 one-component frame, one
// one-code Huffman table each for DC and AC (the code "0": DC difference 0,
// and end of block), the scan ("00" padded with ones) and EOI.
inline std::string minimal_jpeg() {
    auto segment = [](unsigned char marker, const std::string& payload) {
        const auto n = payload.size() + 2;
        return std::string{'\xFF', static_cast<char>(marker), static_cast<char>(n >> 8U),
                           static_cast<char>(n & 0xFFU)} +
               payload;
    };
    const std::string jfif("JFIF\0\x01\x01\0\0\x01\0\x01\0\0", 14);
    std::string dqt(1, '\0');
    dqt += std::string(64, '\x01');
    const std::string sof("\x08\0\x08\0\x08\x01\x01\x11\0", 9);
    auto dht = [](char table) {
        std::string t(1, table);
        t += '\x01';
        t += std::string(15, '\0');
        t += '\0';  // the one symbol: 0
        return t;
    };
    const std::string sos("\x01\x01\0\0\x3F\0", 6);
    return std::string("\xFF\xD8", 2) + segment(0xE0, jfif) + segment(0xDB, dqt) +
           segment(0xC0, sof) + segment(0xC4, dht('\0')) + segment(0xC4, dht('\x10')) +
           segment(0xDA, sos) + std::string("\x3F\xFF\xD9", 3);
}

}  // namespace gport::testing
