// The monitor's connection to gportd, on the blocking client library:
// subscribes to attitude, link and motion, polls status twice a second,
// reconnects when the daemon goes away, and sends the monitor's commands.
// Everything it learns goes into a MonitorState.
#pragma once

#include <chrono>
#include <optional>
#include <string>

#include "gport/client/client.hpp"
#include "state.hpp"

namespace gport::cli::monitor {

inline constexpr auto kStatusEvery = std::chrono::milliseconds(500);
inline constexpr auto kReconnectEvery = std::chrono::milliseconds(1000);
inline constexpr double kAttitudeRateHz = 20;
// A nudge: one speed of this duration (and lease) per arrow key press.
inline constexpr auto kNudgeDuration = std::chrono::milliseconds(300);

// The moment now: steady time and the local wall clock as HH:MM:SS.
Now current_time();

class Feed {
  public:
    Feed(std::string socket, bool control);

    // The first connection; throws client::Error (kTransport when gportd
    // cannot be reached, the daemon's error when control is refused).
    void open();
    // Reads notifications for up to `wait`, polls status when due and
    // reconnects when the connection is gone. Does not throw client::Error.
    void pump(std::chrono::milliseconds wait);
    void center();
    void nudge(const client::Axes& speed);
    // Releases control (when held) and disconnects.
    void close();

    MonitorModel model() const { return state_.model(current_time()); }

  private:
    void connect();
    void poll_status();
    void lost(const client::Error& error);
    // Runs a command; its error becomes an event.
    template <typename Call>
    void command(const char* what, Call&& call);

    std::string socket_;
    bool control_;
    MonitorState state_;
    std::optional<client::Client> client_;
    std::chrono::steady_clock::time_point next_status_{};
    std::chrono::steady_clock::time_point next_connect_{};
};

}  // namespace gport::cli::monitor
