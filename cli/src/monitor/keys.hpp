// The monitor's keys, parsed from the bytes a terminal sends (pure).
#pragma once

#include <string>
#include <vector>

namespace gport::cli::monitor {

enum class Key { kQuit, kCentre, kLeft, kRight, kUp, kDown };

// Takes the keys out of the front of `pending` (bytes read from the
// terminal): q/Q, c/C and the arrows (ESC [ A-D or ESC O A-D). Other bytes
// are dropped; an escape sequence cut short at the end stays in `pending`
// for the next read.
std::vector<Key> take_keys(std::string& pending);

}  // namespace gport::cli::monitor
