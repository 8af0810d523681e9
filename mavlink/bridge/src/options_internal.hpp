// What options.cpp (the command line) and options_config.cpp (the config
// file's `mavlink` section) share.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "gport/mavlink/bridge/options.hpp"

namespace gport::mavlink::bridge::detail {

inline constexpr std::array<std::string_view, 7> kLogLevels = {"trace", "debug",    "info", "warn",
                                                               "error", "critical", "off"};

// The one rule for a MAVLink system or component id, whichever source
// (a command-line number, a config integer) it comes from: 1 to 255.
inline std::optional<std::uint8_t> mavlink_id(long long value) {
    if (value < 1 || value > 255) {
        return std::nullopt;
    }
    return static_cast<std::uint8_t>(value);
}

// Checks the values both sources share; empty when all is well.
std::string check(const Options& o);

// Applies the `mavlink` section of a config file; returns the error text.
std::string apply_config(const std::string& path, Options& o);

}  // namespace gport::mavlink::bridge::detail
