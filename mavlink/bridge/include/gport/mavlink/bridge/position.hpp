// Which GLOBAL_POSITION_INT gport-mavlink takes as the vehicle's position
// (photo geotags: CAMERA_IMAGE_CAPTURED and gportd's capture meta;
// docs/mavlink.md, "The camera component"), pure (issue 30). The trust
// rules (trust.hpp) already limit vehicle state to the vehicle's system
// id; of that system only the autopilot's component (compid 1,
// MAV_COMP_ID_AUTOPILOT1: ArduPilot's and PX4's) speaks for the vehicle,
// and only a position inside these bounds is a position:
//
//   field          unit      taken
//   lat            degE7     -90° .. +90°
//   lon            degE7     -180° .. +180°
//   alt            mm AMSL   -1000 m .. 20000 m (the Dead Sea's shore is
//                            at -430 m; 20 km is far above any gimbal's
//                            flight)
//   relative_alt   mm        -21000 m .. 21000 m (alt minus home's, both
//                            in the range above)
//
// INT32_MAX / INT32_MIN ("unknown" in some autopilots' fields, or a
// forged frame: "lat 214.7483647", "alt_m -2147483.648") fall outside.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "gport/mavlink/frame.hpp"
#include "gport/mavlink/message_types.hpp"

namespace gport::mavlink::bridge {

inline constexpr std::int32_t kMaxLatitudeDegE7 = 900'000'000;
inline constexpr std::int32_t kMaxLongitudeDegE7 = 1'800'000'000;
inline constexpr std::int32_t kMinAltitudeMm = -1'000'000;
inline constexpr std::int32_t kMaxAltitudeMm = 20'000'000;
inline constexpr std::int32_t kMaxRelativeAltitudeMm = 21'000'000;

// Why a position from `from` (a frame the trust rules passed) is not taken,
// naming the component or the value and the bounds; empty when it is taken.
std::optional<std::string> position_problem(const Header& from, const GlobalPositionInt& position);

}  // namespace gport::mavlink::bridge
