// What the monitor knows: MonitorState takes the daemon's notifications,
// polled statuses and the monitor's own doings, each with the time it
// happened, and produces a MonitorModel — everything one frame shows, with
// ages and time left worked out for a given moment. Pure: no I/O, no clock
// of its own, so it is tested with made-up times.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "gport/client/types.hpp"

namespace gport::cli::monitor {

using SteadyTime = std::chrono::steady_clock::time_point;

// A moment: the steady time for ages, the wall clock ("HH:MM:SS") for display.
struct Now {
    SteadyTime steady{};
    std::string clock{};
};

enum class Severity { kInfo, kGood, kWarn, kBad };

struct EventLine {
    std::string clock{};
    std::string text{};
    Severity severity = Severity::kInfo;
};

struct MotionView {
    std::string mode{};
    std::string owner{};                   // "you", "pid 812 (client 4)", "nobody"
    std::optional<client::Axes> speed{};   // speed motions, °/s
    std::optional<client::Axes> target{};  // angle and centre motions, °
    std::optional<std::int64_t> time_left_ms{};
    std::optional<std::int64_t> elapsed_ms{};
};

struct MotionEnd {
    std::string mode{};
    std::string reason{};
    std::string clock{};
};

struct MonitorModel {
    std::string socket{};
    std::string clock{};
    bool connected = false;
    std::string connection_error{};  // why not connected
    std::string stale_since{};       // "HH:MM:SS" the connection was lost; values from before
    std::string daemon_version{};
    std::optional<std::int64_t> uptime_ms{};
    std::string link_state{"unknown"};  // up, stale, down, unknown
    std::string link_reason{};
    std::string device{};
    bool device_open = false;
    std::optional<std::int64_t> attitude_age_ms{};
    std::optional<client::AttitudeSample> attitude{};
    std::optional<MotionView> motion{};
    std::optional<MotionEnd> last_end{};
    std::string controller{"unknown"};  // "free", "you", "pid 812 (client 4)"
    bool control_requested = false;     // --control
    bool holds_control = false;
    std::optional<client::Counters> counters{};
    std::optional<double> frame_rate_hz{};  // attitude frames per second, from two polls
    std::int64_t clients = 0;
    std::uint64_t dropped_total = 0;  // attitude notifications dropped, all clients
    std::uint64_t dropped_self = 0;   // ... for this monitor
    std::string recording{};
    std::vector<EventLine> events{};  // the latest kMaxEvents, oldest first
    std::uint64_t events_total = 0;   // events noted since the start
};

class MonitorState {
  public:
    static constexpr std::size_t kMaxEvents = 32;

    MonitorState(std::string socket, bool control_requested);

    void on_connected(const Now& now);
    void on_disconnected(const std::string& why, const Now& now);
    void on_status(const client::Status& status, const Now& now);
    void on_notification(const client::Notification& notification, const Now& now);
    void on_control(bool holds, const Now& now);
    // One line in the event list (the monitor's own actions and errors).
    void note(std::string text, Severity severity, const Now& now);

    MonitorModel model(const Now& now) const;

  private:
    struct TimedMotion {
        MotionView view{};
        SteadyTime seen{};  // when time_left_ms / elapsed_ms were true
    };

    void on_attitude(const client::AttitudeSample& sample, const Now& now);
    void on_link(const client::LinkEvent& event, const Now& now);
    void on_motion(const client::MotionEvent& event, const Now& now);
    void set_link(const std::string& state, const std::string& reason, const Now& now);
    MotionView view_of(const client::Motion& motion) const;

    MonitorModel base_;  // the fields that need no time arithmetic
    std::int64_t self_id_ = 0;
    std::optional<TimedMotion> motion_;
    std::optional<SteadyTime> last_sample_at_;
    std::optional<std::pair<SteadyTime, std::int64_t>> status_age_;  // polled attitude age
    std::optional<std::pair<SteadyTime, std::int64_t>> uptime_;
    std::optional<std::pair<SteadyTime, std::uint64_t>> frames_seen_;
    std::deque<EventLine> events_;
};

}  // namespace gport::cli::monitor
