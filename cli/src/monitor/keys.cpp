#include "keys.hpp"

namespace gport::cli::monitor {
namespace {

constexpr char kEscape = '\x1b';

bool arrow(char final_byte, Key& key) {
    switch (final_byte) {
        case 'A':
            key = Key::kUp;
            return true;
        case 'B':
            key = Key::kDown;
            return true;
        case 'C':
            key = Key::kRight;
            return true;
        case 'D':
            key = Key::kLeft;
            return true;
        default:
            return false;
    }
}

// Length of the escape sequence at `i` (CSI or SS3), 0 when cut short.
std::size_t escape_length(const std::string& bytes, std::size_t i) {
    if (i + 1 >= bytes.size()) {
        return 0;
    }
    const char kind = bytes[i + 1];
    if (kind == 'O') {
        return i + 2 < bytes.size() ? 3 : 0;
    }
    if (kind != '[') {
        return 1;  // a lone ESC followed by something else: drop the ESC
    }
    for (std::size_t j = i + 2; j < bytes.size(); ++j) {
        const auto c = static_cast<unsigned char>(bytes[j]);
        if (c >= 0x40 && c <= 0x7E) {  // the final byte of a CSI sequence
            return j - i + 1;
        }
    }
    return 0;
}

}  // namespace

std::vector<Key> take_keys(std::string& pending) {
    std::vector<Key> keys;
    std::size_t i = 0;
    while (i < pending.size()) {
        const char c = pending[i];
        if (c != kEscape) {
            if (c == 'q' || c == 'Q') {
                keys.push_back(Key::kQuit);
            } else if (c == 'c' || c == 'C') {
                keys.push_back(Key::kCentre);
            }
            ++i;
            continue;
        }
        const std::size_t length = escape_length(pending, i);
        if (length == 0) {
            break;  // wait for the rest
        }
        Key key{};
        if (length >= 3 && arrow(pending[i + length - 1], key)) {
            keys.push_back(key);
        }
        i += length;
    }
    pending.erase(0, i);
    return keys;
}

}  // namespace gport::cli::monitor
