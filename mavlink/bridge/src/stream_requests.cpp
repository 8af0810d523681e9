#include "gport/mavlink/bridge/stream_requests.hpp"

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

}  // namespace gport::mavlink::bridge
