// Geotag by default (docs/mavlink.md, "Position and attitude"): the
// messages gport-mavlink needs from the vehicle's autopilot (component 1),
// asked for with MAV_CMD_SET_MESSAGE_INTERVAL when they do not arrive.
// ArduPilot's default stream rates leave GLOBAL_POSITION_INT off a serial
// port unless MAVn_POSITION (SRn_POSITION) is set; PX4 streams by the
// link's mode. Both apply SET_MESSAGE_INTERVAL to the link it came in on.
//
//   A stream is due when the autopilot's heartbeat came at least kGrace
//   ago, the message has not arrived for kGrace, fewer than kAttempts
//   requests went out since it last arrived, and the last one is kRetry
//   old. An arrival resets the count: a stream lost later is asked for
//   again, kAttempts times.
//
// Pure: the caller gives the time and sends.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace gport::mavlink::bridge {

class StreamRequests {
  public:
    using Clock = std::chrono::steady_clock;
    static constexpr std::chrono::seconds kGrace{3};
    static constexpr std::chrono::seconds kRetry{3};
    static constexpr std::uint32_t kAttempts = 3;

    struct Stream {
        std::uint32_t msgid = 0;
        std::uint32_t interval_us = 0;  // SET_MESSAGE_INTERVAL's param2
    };

    explicit StreamRequests(const std::vector<Stream>& wanted);

    // The vehicle's autopilot sent a heartbeat.
    void on_heartbeat(Clock::time_point now);
    // A message arrived from the vehicle's autopilot (others are ignored).
    void on_message(std::uint32_t msgid, Clock::time_point now);
    // The streams to ask for now; each counts as a request sent.
    std::vector<Stream> due(Clock::time_point now);
    // Requests sent for `msgid` since it last arrived.
    std::uint32_t attempts(std::uint32_t msgid) const;

  private:
    struct State {
        Stream stream;
        std::optional<Clock::time_point> seen;
        std::optional<Clock::time_point> asked;
        std::uint32_t attempts = 0;
    };
    bool is_due(const State& state, Clock::time_point now) const;

    std::vector<State> states_;
    std::optional<Clock::time_point> heartbeat_;  // the first
};

// The one warning for a photo without a position: what to set on each
// autopilot. PX4's Gimbal-mode link streams no GLOBAL_POSITION_INT and
// answered no SET_MESSAGE_INTERVAL in SITL (issue 31): its remedy is an
// Onboard link. `asked`: the requests sent since the position last came.
std::string no_position_warning(std::int32_t image_index, std::uint8_t sysid,
                                std::chrono::milliseconds max_age, std::uint32_t asked);

}  // namespace gport::mavlink::bridge
