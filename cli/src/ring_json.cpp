// watch --shared-memory: ring samples as gportd's attitude notifications.
#include <cmath>
#include <cstdint>

#include "gport/cli/output.hpp"

namespace gport::cli {
namespace {

using nlohmann::json;

// gportd prints numbers with fmt's shortest form, so a whole value has no
// fraction and reads back as an integer; the same here.
json as_printed(double value) {
    const double whole = std::trunc(value);
    if (whole == value && std::fabs(value) < 9.0e15) {
        return static_cast<std::int64_t>(whole);
    }
    return value;
}

json axes(const client::Axes& a) {
    return {
        {"roll", as_printed(a.roll)}, {"pitch", as_printed(a.pitch)}, {"yaw", as_printed(a.yaw)}};
}

}  // namespace

json attitude_notification(const client::AttitudeSample& sample) {
    // "t" always has six decimals in gportd's text, so it reads as a double.
    json params = {{"seq", sample.seq},
                   {"t", sample.time},
                   {"imu", axes(sample.imu)},
                   {"hall", axes(sample.hall)}};
    if (sample.rates) {
        params["rates"] = {{"hall", axes(sample.rates->hall)},
                           {"imu",
                            {{"x", as_printed(sample.rates->imu.x)},
                             {"y", as_printed(sample.rates->imu.y)},
                             {"z", as_printed(sample.rates->imu.z)}}}};
    }
    if (sample.dropped > 0) {
        params["dropped"] = sample.dropped;
    }
    return {{"jsonrpc", "2.0"}, {"method", "attitude"}, {"params", std::move(params)}};
}

}  // namespace gport::cli
