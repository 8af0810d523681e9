#include "gport/config/advisories.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <utility>

namespace gport::config {
namespace {

struct Policy {
    const char* key;
    Failsafe FailsafeConfig::*member;
};

constexpr std::array<Policy, 3> kPolicies{{
    {"on_owner_gone", &FailsafeConfig::on_owner_gone},
    {"on_shutdown", &FailsafeConfig::on_shutdown},
    {"on_link_lost", &FailsafeConfig::on_link_lost},
}};

struct Axis {
    const char* name;
    AxisRange LimitsConfig::*range;
};

constexpr std::array<Axis, 3> kAxes{{
    {"roll", &LimitsConfig::roll},
    {"pitch", &LimitsConfig::pitch},
    {"yaw", &LimitsConfig::yaw},
}};

// The failsafe's centre is clamped into the soft limits, as `center` is:
// accepted (the gimbal still ends inside its limits), but worth a word.
void center_outside_limits(const Config& config, std::vector<std::string>& out) {
    std::string policies;
    for (const auto& policy : kPolicies) {
        if (config.failsafe.*policy.member == Failsafe::kCenter) {
            policies += fmt::format("{}failsafe.{}", policies.empty() ? "" : ", ", policy.key);
        }
    }
    if (policies.empty()) {
        return;
    }
    for (const auto& axis : kAxes) {
        const AxisRange& range = config.limits.*axis.range;
        if (range.min <= 0 && range.max >= 0) {
            continue;
        }
        const double nearest = std::clamp(0.0, range.min, range.max);
        out.push_back(fmt::format(
            "{} is \"center\", but 0° lies outside limits.{} ({} to {}): the failsafe's centre "
            "(like the center command) aims {} at {}° instead",
            policies, axis.name, range.min, range.max, axis.name, nearest));
    }
}

}  // namespace

std::vector<std::string> advisories(const Config& config) {
    std::vector<std::string> out;
    center_outside_limits(config, out);
    return out;
}

}  // namespace gport::config
