#include "gport/mavlink/bridge/position.hpp"

#include <fmt/format.h>

#include "gport/mavlink/enums.hpp"

namespace gport::mavlink::bridge {

namespace {

bool within(std::int32_t value, std::int32_t low, std::int32_t high) {
    return value >= low && value <= high;
}

}  // namespace

std::optional<std::string> position_problem(const Header& from, const GlobalPositionInt& position) {
    if (from.compid != mav_comp_id::kAutopilot1) {
        return fmt::format(
            "component {} is not the vehicle's autopilot (component {}, which alone gives the "
            "vehicle's position)",
            from.compid, mav_comp_id::kAutopilot1);
    }
    if (!within(position.lat, -kMaxLatitudeDegE7, kMaxLatitudeDegE7)) {
        return fmt::format("lat {:.7f} is outside -90..90", position.lat / 1e7);
    }
    if (!within(position.lon, -kMaxLongitudeDegE7, kMaxLongitudeDegE7)) {
        return fmt::format("lon {:.7f} is outside -180..180", position.lon / 1e7);
    }
    if (!within(position.alt, kMinAltitudeMm, kMaxAltitudeMm)) {
        return fmt::format("alt_m {:.3f} is outside {}..{} m AMSL", position.alt / 1e3,
                           kMinAltitudeMm / 1000, kMaxAltitudeMm / 1000);
    }
    if (!within(position.relative_alt, -kMaxRelativeAltitudeMm, kMaxRelativeAltitudeMm)) {
        return fmt::format("relative_alt_m {:.3f} is outside -{}..{} m",
                           position.relative_alt / 1e3, kMaxRelativeAltitudeMm / 1000,
                           kMaxRelativeAltitudeMm / 1000);
    }
    return std::nullopt;
}

}  // namespace gport::mavlink::bridge
