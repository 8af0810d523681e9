#include "gport/daemon/core/soft_brake.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <optional>

#include "limit_axes.hpp"

namespace gport::daemon {
namespace {

using detail::kLimitAxes;
using protocol::from_centi;

// The side of `range` that a motion at `speed` approaches, if it is
// narrowed (the defaults, ±327.67, are the protocol's end: no limit).
std::optional<double> approached_side(const config::AxisRange& range, std::int16_t speed) {
    if (speed > 0 && range.max < config::kMaxDegrees) {
        return range.max;
    }
    if (speed < 0 && range.min > -config::kMaxDegrees) {
        return range.min;
    }
    return std::nullopt;
}

}  // namespace

std::vector<std::string> SoftBrake::needs_attitude(protocol::Axes speed) const {
    std::vector<std::string> out;
    for (const auto& axis : kLimitAxes) {
        if (approached_side(limits_.*axis.range, speed.*axis.member)) {
            out.emplace_back(axis.name);
        }
    }
    return out;
}

double SoftBrake::distance(double speed_deg_s, Millis age) const {
    const auto ahead = std::chrono::duration<double>(std::max(age, Millis(0)) + lookahead_);
    return std::abs(speed_deg_s) * ahead.count() + limits_.braking_margin_deg;
}

Braked SoftBrake::apply(protocol::Axes speed, const protocol::Axes& hall, Millis age) const {
    Braked out{speed, {}};
    for (const auto& axis : kLimitAxes) {
        auto& value = out.speed.*axis.member;
        const auto side = approached_side(limits_.*axis.range, value);
        if (!side) {
            continue;
        }
        const double angle = from_centi(hall.*axis.member);
        const double left = value > 0 ? *side - angle : angle - *side;  // < 0: beyond it
        if (left <= distance(from_centi(value), age)) {
            value = 0;
            out.braked.emplace_back(axis.name);
        }
    }
    return out;
}

bool moves(const protocol::Axes& speed) {
    return speed.roll != 0 || speed.pitch != 0 || speed.yaw != 0;
}

std::vector<std::string> merged(const std::vector<std::string>& a,
                                const std::vector<std::string>& b) {
    std::vector<std::string> out;
    for (const auto& axis : kLimitAxes) {
        const auto in = [&](const std::vector<std::string>& v) {
            return std::find(v.begin(), v.end(), axis.name) != v.end();
        };
        if (in(a) || in(b)) {
            out.emplace_back(axis.name);
        }
    }
    return out;
}

}  // namespace gport::daemon
