#include "gport/mavlink/bridge/stream_requests.hpp"

#include <fmt/format.h>

namespace gport::mavlink::bridge {

StreamRequests::StreamRequests(const std::vector<Stream>& wanted) {
    for (const auto& stream : wanted) {
        State state;
        state.stream = stream;
        states_.push_back(state);
    }
}

void StreamRequests::on_heartbeat(Clock::time_point now) {
    if (!heartbeat_) {
        heartbeat_ = now;
    }
}

void StreamRequests::on_message(std::uint32_t msgid, Clock::time_point now) {
    for (auto& state : states_) {
        if (state.stream.msgid == msgid) {
            state.seen = now;
            state.attempts = 0;
            state.asked.reset();
        }
    }
}

bool StreamRequests::is_due(const State& state, Clock::time_point now) const {
    if (!heartbeat_ || now - *heartbeat_ < kGrace || state.attempts >= kAttempts) {
        return false;
    }
    if (state.seen && now - *state.seen < kGrace) {
        return false;
    }
    return !state.asked || now - *state.asked >= kRetry;
}

std::vector<StreamRequests::Stream> StreamRequests::due(Clock::time_point now) {
    std::vector<Stream> out;
    for (auto& state : states_) {
        if (is_due(state, now)) {
            state.asked = now;
            ++state.attempts;
            out.push_back(state.stream);
        }
    }
    return out;
}

std::uint32_t StreamRequests::attempts(std::uint32_t msgid) const {
    for (const auto& state : states_) {
        if (state.stream.msgid == msgid) {
            return state.attempts;
        }
    }
    return 0;
}

std::string no_position_warning(std::int32_t image_index, std::uint8_t sysid,
                                std::chrono::milliseconds max_age, std::uint32_t asked) {
    return fmt::format(
        "camera: image_index {} has no position: no GLOBAL_POSITION_INT from the vehicle's "
        "autopilot (system {} component 1) in the last {} ms{}. Its link to gport-mavlink must "
        "stream it: ArduPilot: MAVn_POSITION (SRn_POSITION in older firmware; n the serial "
        "port's MAVLink instance) to 5 Hz or more; PX4: an Onboard link (MAV_x_MODE Onboard; a "
        "link in Gimbal mode streams no position and answers no SET_MESSAGE_INTERVAL). Said "
        "once per run",
        image_index, sysid, max_age.count(),
        asked > 0 ? fmt::format("; asked for it {} time(s) with SET_MESSAGE_INTERVAL", asked)
                  : std::string());
}

}  // namespace gport::mavlink::bridge
