#include "gport/ipc/event_json.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <iterator>

#include "json_common.hpp"

namespace gport::ipc {
namespace {

using detail::axes_json;
using detail::client_json;
using detail::degrees;
using nlohmann::json;

void append_axes(fmt::memory_buffer& out, const protocol::Axes& axes) {
    fmt::format_to(std::back_inserter(out), R"({{"roll":{},"pitch":{},"yaw":{}}})",
                   degrees(axes.roll), degrees(axes.pitch), degrees(axes.yaw));
}

// "t" is printed from integer microseconds so that it is exact, whatever a
// double would round it to.
void append_time(fmt::memory_buffer& out, daemon::WallTime time) {
    const auto us =
        std::chrono::duration_cast<std::chrono::microseconds>(time.time_since_epoch()).count();
    const auto seconds = us / 1'000'000;
    const auto fraction = us % 1'000'000;
    if (us < 0) {  // before 1970: a broken clock, still valid JSON
        fmt::format_to(std::back_inserter(out), "{}", static_cast<double>(us) / 1e6);
        return;
    }
    fmt::format_to(std::back_inserter(out), "{}.{:06}", seconds, fraction);
}

// A number as attitude_payload prints it: fmt writes a whole double without a
// fraction ("0", "-1"), which JSON reads as an integer, so attitude_json
// holds whole values as integers and serialises to the same text.
json as_printed(double value) {
    const double whole = std::trunc(value);
    if (whole == value && std::fabs(value) < 9.0e15) {
        return static_cast<std::int64_t>(whole);
    }
    return value;
}

json printed_axes(const protocol::Axes& axes) {
    return {{"roll", as_printed(degrees(axes.roll))},
            {"pitch", as_printed(degrees(axes.pitch))},
            {"yaw", as_printed(degrees(axes.yaw))}};
}

Line notification(std::string_view topic, json params) {
    json message = {{"jsonrpc", "2.0"}, {"method", topic}, {"params", std::move(params)}};
    return std::make_shared<const std::string>(detail::json_line(message));
}

}  // namespace

std::string attitude_payload(const daemon::AttitudeSample& sample) {
    fmt::memory_buffer out;
    const auto& a = sample.attitude;
    fmt::format_to(std::back_inserter(out), R"({{"seq":{},"t":)", sample.seq);
    append_time(out, sample.wall);
    fmt::format_to(std::back_inserter(out), R"(,"imu":)");
    append_axes(out, a.imu);
    fmt::format_to(std::back_inserter(out), R"(,"hall":)");
    append_axes(out, a.hall);
    if (a.rates) {
        fmt::format_to(std::back_inserter(out), R"(,"rates":{{"hall":)");
        append_axes(out, a.rates->hall);
        fmt::format_to(std::back_inserter(out), R"(,"imu":{{"x":{},"y":{},"z":{}}}}})",
                       degrees(a.rates->imu_x), degrees(a.rates->imu_y), degrees(a.rates->imu_z));
    }
    out.push_back('}');
    return fmt::to_string(out);
}

Line attitude_line(const daemon::AttitudeSample& sample) {
    std::string line = R"({"jsonrpc":"2.0","method":"attitude","params":)";
    line += attitude_payload(sample);
    line += "}\n";
    return std::make_shared<const std::string>(std::move(line));
}

Line with_dropped(const std::string& attitude_notification, std::uint64_t dropped) {
    // The line ends with the payload's '}', the message's '}' and '\n'.
    std::string line = attitude_notification;
    if (line.size() < 3) {
        return std::make_shared<const std::string>(std::move(line));
    }
    line.insert(line.size() - 3, fmt::format(R"(,"dropped":{})", dropped));
    return std::make_shared<const std::string>(std::move(line));
}

Line link_line(const daemon::LinkEvent& event) {
    return notification("link",
                        {{"state", daemon::to_string(event.state)}, {"reason", event.reason}});
}

Line motion_line(const daemon::MotionEvent& event) {
    json params = {{"change", daemon::to_string(event.change)},
                   {"mode", daemon::to_string(event.mode)},
                   {"owner", event.owner ? client_json(*event.owner) : json(nullptr)}};
    if (event.mode == daemon::MotionMode::kSpeed) {
        params["speed"] = axes_json(event.speed);
        params["duration_ms"] = event.duration.count();
    } else if (event.mode == daemon::MotionMode::kAngle) {
        params["angle"] = axes_json(event.angle);  // as before tracking: kept for old clients
        params["target"] = axes_json(event.angle);
    } else if (event.mode == daemon::MotionMode::kCenter) {
        params["target"] = axes_json(event.angle);  // 0/0/0
    }
    if (!event.clamped.empty()) {
        params["clamped"] = event.clamped;  // the soft limits moved the target
    }
    if (event.reason) {
        params["reason"] = daemon::to_string(*event.reason);
    }
    if (event.reason == daemon::EndReason::kLimit) {
        params["braked"] = event.braked;
    }
    return notification("motion", std::move(params));
}

json attitude_json(const daemon::AttitudeSample& sample) {
    const auto& a = sample.attitude;
    // "t" always has six decimals, except before 1970 (see append_time).
    const double t = detail::epoch_seconds(sample.wall);
    json payload = {{"seq", sample.seq},
                    {"t", sample.wall.time_since_epoch().count() < 0 ? as_printed(t) : json(t)},
                    {"imu", printed_axes(a.imu)},
                    {"hall", printed_axes(a.hall)}};
    if (a.rates) {
        payload["rates"] = {{"hall", printed_axes(a.rates->hall)},
                            {"imu",
                             {{"x", as_printed(degrees(a.rates->imu_x))},
                              {"y", as_printed(degrees(a.rates->imu_y))},
                              {"z", as_printed(degrees(a.rates->imu_z))}}}};
    }
    return payload;
}

Line capture_line(const json& capture) {
    return notification("capture", capture);
}

}  // namespace gport::ipc
