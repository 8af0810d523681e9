// Small formatting helpers shared by the monitor's state and renderer.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "gport/client/types.hpp"

namespace gport::cli::monitor {

// "+12.3°" / "-0.5°" (sign always shown), with `decimals` places and `unit`.
std::string signed_value(double value, int decimals, const char* unit);
// "roll +1.0 pitch -2.0 yaw +30.0 °/s" (axes that are zero left out unless all are).
std::string axes_text(const client::Axes& axes, const char* unit);
// "you", "pid 812 (client 4)" or "nobody".
std::string peer_text(const std::optional<client::Peer>& peer, std::int64_t self_id);
// "0.4 s", "12 s", "3m 05s", "2h 03m".
std::string duration_text(std::int64_t ms);
// `text` in rows of at most `width` columns, broken at spaces; a word longer
// than a row (a path) is broken where it reaches the end of the row.
std::vector<std::string> wrap(const std::string& text, int width);
// Pads with spaces or cuts to exactly `width` columns (UTF-8 aware).
std::string fit(const std::string& text, int width);

}  // namespace gport::cli::monitor
