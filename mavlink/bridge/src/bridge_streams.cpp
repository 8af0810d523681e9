// Geotag by default: the autopilot's GLOBAL_POSITION_INT and ATTITUDE asked
// for with MAV_CMD_SET_MESSAGE_INTERVAL when they do not come
// (stream_requests.hpp), its answers, and the one warning for a photo
// without a position (docs/mavlink.md, "Position and attitude").
#include <spdlog/spdlog.h>

#include "bridge.hpp"
#include "gport/mavlink/enums.hpp"

namespace gport::mavlink::bridge {

namespace {

std::string_view stream_name(std::uint32_t msgid) {
    const MessageInfo* info = find_message(msgid);
    return info != nullptr ? info->name : "a message";
}

}  // namespace

void Bridge::request_streams() {
    const auto vehicle = trust_.vehicle();
    if (!vehicle) {
        return;
    }
    for (const auto& stream : streams_.due(Clock::now())) {
        CommandLong command;
        command.target_system = *vehicle;
        command.target_component = mav_comp_id::kAutopilot1;
        command.command = mav_cmd::kSetMessageInterval;
        command.param[0] = static_cast<float>(stream.msgid);
        command.param[1] = static_cast<float>(stream.interval_us);
        send(command);
        // The first request of a loss at info, its retries at debug.
        const auto attempt = streams_.attempts(stream.msgid);
        spdlog::log(attempt == 1 ? spdlog::level::info : spdlog::level::debug,
                    "mavlink: no {} from the vehicle's autopilot (system {} component 1) for {} s; "
                    "asking for it at {} Hz with SET_MESSAGE_INTERVAL (request {} of {})",
                    stream_name(stream.msgid), *vehicle, StreamRequests::kGrace.count(),
                    1000000 / stream.interval_us, attempt, StreamRequests::kAttempts);
    }
}

void Bridge::on_ack(const Header& from, const CommandAck& message) {
    if (message.command != mav_cmd::kSetMessageInterval || from.sysid != trust_.vehicle()) {
        return;
    }
    if (message.result == mav_result::kAccepted) {
        spdlog::debug(
            "mavlink: system {} component {} answered SET_MESSAGE_INTERVAL with result "
            "{} (ACCEPTED)",
            from.sysid, from.compid, message.result);
        return;
    }
    // Through the log book: the vehicle's system may send as many as it likes.
    log_.warn("mavlink: SET_MESSAGE_INTERVAL refused", [&] {
        return fmt::format(
            "mavlink: system {} component {} answered SET_MESSAGE_INTERVAL with result {}; "
            "further refusals are counted, one line a minute",
            from.sysid, from.compid, message.result);
    });
}

}  // namespace gport::mavlink::bridge
