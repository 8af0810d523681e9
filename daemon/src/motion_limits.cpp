#include "gport/daemon/core/motion_limits.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "limit_axes.hpp"

namespace gport::daemon {
namespace {

using detail::kLimitAxes;
using protocol::clamped_centi;
using protocol::from_centi;

}  // namespace

Outcome<Limited> MotionLimits::angle(protocol::Axes target, bool clamp) const {
    Limited out{target, {}};
    for (const auto& axis : kLimitAxes) {
        const auto& range = config_.*axis.range;
        const auto low = clamped_centi(range.min);
        const auto high = clamped_centi(range.max);
        auto& value = out.axes.*axis.member;
        if (value >= low && value <= high) {
            continue;
        }
        if (!clamp) {
            return CommandError{
                ErrorCode::kInvalidParams,
                fmt::format("{} = {} is outside the soft limit {} to {} (limits.{}); "
                            "clamp: true moves as far as allowed",
                            axis.name, from_centi(value), range.min, range.max, axis.name)};
        }
        value = std::clamp(value, low, high);
        out.clamped.emplace_back(axis.name);
    }
    return out;
}

Limited MotionLimits::center_target() const {
    return *angle(protocol::Axes{}, true);  // with clamp, angle() never refuses
}

Outcome<Limited> MotionLimits::speed(protocol::Axes speed, bool clamp) const {
    Limited out{speed, {}};
    const auto max = clamped_centi(config_.max_speed);
    for (const auto& axis : kLimitAxes) {
        auto& value = out.axes.*axis.member;
        if (std::abs(value) <= max) {
            continue;
        }
        if (!clamp) {
            return CommandError{ErrorCode::kInvalidParams,
                                fmt::format("{} = {} °/s is faster than the soft limit {} °/s "
                                            "(limits.max_speed); clamp: true moves at the limit",
                                            axis.name, from_centi(value), config_.max_speed)};
        }
        value = static_cast<std::int16_t>(value < 0 ? -max : max);
        out.clamped.emplace_back(axis.name);
    }
    return out;
}

}  // namespace gport::daemon
