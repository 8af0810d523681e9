// The three axes as the soft limits see them: a name for messages, the
// command's member (0.01 units) and the axis's range in LimitsConfig. Shared
// by MotionLimits (checks commands) and SoftBrake (brakes running motions).
#pragma once

#include <array>
#include <cstdint>

#include "gport/config/config.hpp"
#include "gport/protocol/messages.hpp"

namespace gport::daemon::detail {

struct LimitAxis {
    const char* name;
    std::int16_t protocol::Axes::*member;
    config::AxisRange config::LimitsConfig::*range;
};

inline constexpr std::array<LimitAxis, 3> kLimitAxes = {
    LimitAxis{"roll", &protocol::Axes::roll, &config::LimitsConfig::roll},
    LimitAxis{"pitch", &protocol::Axes::pitch, &config::LimitsConfig::pitch},
    LimitAxis{"yaw", &protocol::Axes::yaw, &config::LimitsConfig::yaw}};

}  // namespace gport::daemon::detail
