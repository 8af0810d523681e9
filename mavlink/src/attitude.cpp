#include "gport/mavlink/attitude.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace gport::mavlink {

double wrap_degrees(double degrees) {
    double r = std::fmod(degrees, 360.0);
    if (r > 180.0) {
        r -= 360.0;
    } else if (r <= -180.0) {
        r += 360.0;
    }
    return r;
}

Quaternion to_quaternion(const Euler& angles) {
    const double half_roll = to_radians(wrap_degrees(angles.roll)) / 2;
    const double half_pitch = to_radians(wrap_degrees(angles.pitch)) / 2;
    const double half_yaw = to_radians(wrap_degrees(angles.yaw)) / 2;
    const double cr = std::cos(half_roll), sr = std::sin(half_roll);
    const double cp = std::cos(half_pitch), sp = std::sin(half_pitch);
    const double cy = std::cos(half_yaw), sy = std::sin(half_yaw);
    return {static_cast<float>(cr * cp * cy + sr * sp * sy),
            static_cast<float>(sr * cp * cy - cr * sp * sy),
            static_cast<float>(cr * sp * cy + sr * cp * sy),
            static_cast<float>(cr * cp * sy - sr * sp * cy)};
}

bool is_nan(const Quaternion& q) {
    return std::ranges::any_of(q, [](float c) { return std::isnan(c); });
}

Result<Euler> to_euler(const Quaternion& q, std::string_view field) {
    if (!std::ranges::all_of(q, [](float c) { return std::isfinite(c); })) {
        return Error{
            fmt::format("{}: quaternion [{}, {}, {}, {}] has a NaN or infinite "
                        "component; a rotation needs four finite numbers",
                        field, q[0], q[1], q[2], q[3])};
    }
    const double norm = std::sqrt(double{q[0]} * q[0] + double{q[1]} * q[1] + double{q[2]} * q[2] +
                                  double{q[3]} * q[3]);
    if (norm < 1e-6) {
        return Error{
            fmt::format("{}: quaternion [{}, {}, {}, {}] has length {}; a rotation "
                        "needs a non-zero (ideally unit) quaternion",
                        field, q[0], q[1], q[2], q[3], norm)};
    }
    const double a = q[0] / norm, b = q[1] / norm, c = q[2] / norm, d = q[3] / norm;
    const double roll = std::atan2(2 * (c * d + a * b), a * a - b * b - c * c + d * d);
    const double pitch = std::asin(std::clamp(-2 * (b * d - a * c), -1.0, 1.0));
    const double yaw = std::atan2(2 * (b * c + a * d), a * a + b * b - c * c - d * d);
    return Euler{wrap_degrees(to_degrees(roll)), to_degrees(pitch), wrap_degrees(to_degrees(yaw))};
}

}  // namespace gport::mavlink
