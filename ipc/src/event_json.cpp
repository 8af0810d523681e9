#include "gport/ipc/event_json.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cstdint>

#include "gport/contract/attitude_text.hpp"
#include "gport/contract/names.hpp"
#include "json_common.hpp"

namespace gport::ipc {
namespace {

using detail::axes_json;
using detail::client_json;
using nlohmann::json;
using protocol::from_centi;

contract::AttitudePayload::Axes payload_axes(const protocol::Axes& axes) {
    const auto [roll, pitch, yaw] = protocol::degrees_of(axes);
    return {roll, pitch, yaw};
}

Line notification(std::string_view topic, json params) {
    json message = {{"jsonrpc", "2.0"}, {"method", topic}, {"params", std::move(params)}};
    return std::make_shared<const std::string>(detail::json_line(message));
}

}  // namespace

contract::AttitudePayload attitude_payload_of(const daemon::AttitudeSample& sample) {
    const auto& a = sample.attitude;
    contract::AttitudePayload payload;
    payload.seq = sample.seq;
    payload.t_us =
        std::chrono::duration_cast<std::chrono::microseconds>(sample.wall.time_since_epoch())
            .count();
    payload.imu = payload_axes(a.imu);
    payload.hall = payload_axes(a.hall);
    if (a.rates) {
        payload.rates = contract::AttitudePayload::Rates{
            payload_axes(a.rates->hall), from_centi(a.rates->imu_x), from_centi(a.rates->imu_y),
            from_centi(a.rates->imu_z)};
    }
    return payload;
}

std::string attitude_payload(const daemon::AttitudeSample& sample) {
    return contract::attitude_payload_text(attitude_payload_of(sample));
}

AttitudeLine attitude_line(const daemon::AttitudeSample& sample) {
    auto payload = attitude_payload_of(sample);
    auto text = contract::attitude_notification_line(payload);
    return std::make_shared<const AttitudeNotification>(
        AttitudeNotification{std::move(text), std::move(payload)});
}

Line text_of(const AttitudeLine& notification) {
    return {notification, &notification->text};
}

Line with_dropped(const AttitudeNotification& notification, std::uint64_t dropped) {
    auto payload = notification.payload;
    payload.dropped = dropped;
    return std::make_shared<const std::string>(contract::attitude_notification_line(payload));
}

Line link_line(const daemon::LinkEvent& event) {
    return notification(contract::kTopicLink,
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
    if (!event.detail.empty()) {
        params["detail"] = event.detail;  // stalled: where the gimbal stopped
    }
    return notification(contract::kTopicMotion, std::move(params));
}

json attitude_json(const daemon::AttitudeSample& sample) {
    // The payload's own text read back: whole numbers stay integers, and
    // the result says what the notification says, to the last digit.
    return json::parse(attitude_payload(sample));
}

Line capture_line(std::string_view capture) {
    // The capture's text as the log keeps it, spliced (members in the order
    // nlohmann writes them, as every notification).
    std::string line =
        R"({"jsonrpc":"2.0","method":")" + std::string(contract::kTopicCapture) + R"(","params":)";
    line.append(capture);
    line += "}\n";
    return std::make_shared<const std::string>(std::move(line));
}

}  // namespace gport::ipc
