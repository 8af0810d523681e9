// Quaternion <-> Euler angles, as MAVLink's gimbal messages need them.
//
// MAVLink quaternions are {w, x, y, z} (q[0] is the scalar part), rotating
// from the reference frame to the body frame in the aerospace (Z-Y-X)
// sequence: yaw about z (down), then pitch about the new y (right), then
// roll about the new x (forward). Signs follow from NED axes: roll right,
// pitch up, yaw right positive. The formulas are MAVLink's
// mavlink_euler_to_quaternion / mavlink_quaternion_to_euler, restated.
#pragma once

#include <array>
#include <string_view>

#include "gport/mavlink/result.hpp"

namespace gport::mavlink {

struct Euler {  // degrees
    double roll = 0;
    double pitch = 0;
    double yaw = 0;
};

using Quaternion = std::array<float, 4>;  // w, x, y, z

inline constexpr double kPi = 3.14159265358979323846;
constexpr double to_radians(double degrees) {
    return degrees * kPi / 180.0;
}
constexpr double to_degrees(double radians) {
    return radians * 180.0 / kPi;
}

// The angle in (-180, 180].
double wrap_degrees(double degrees);

// The unit quaternion of the angles (any finite values; they are wrapped).
Quaternion to_quaternion(const Euler& angles);

// True when any component is NaN: MAVLink's "no attitude given".
bool is_nan(const Quaternion& q);

// The angles of a quaternion (normalised first), roll and yaw in
// (-180, 180], pitch in [-90, 90]. Refuses NaN or infinite components and a
// quaternion of (near) zero length, naming `field`.
Result<Euler> to_euler(const Quaternion& q, std::string_view field);

}  // namespace gport::mavlink
