// What a camera command must pass before its frame goes to the gimbal: a
// rate a camera can follow (config camera.max_commands_per_s, over all
// clients, a burst of one second's worth), and the journal's pace for them
// (one line per kind, then a summary at most every 10 s, so a flood cannot
// push gportd's other messages out of journald's rate limit). It also keeps
// the recording state, assumed: the protocol has one toggle and no way to
// read the state, so it is what the last toggle made it, unknown at first
// and again whenever the device reopens (the gimbal may have been
// power-cycled).
#pragma once

#include <spdlog/logger.h>

#include <chrono>
#include <cstdint>
#include <optional>
#include <string_view>

#include "gport/base/repeat_limiter.hpp"
#include "gport/base/token_bucket.hpp"
#include "gport/config/config.hpp"
#include "gport/daemon/api.hpp"
#include "gport/daemon/outcome.hpp"

namespace gport::daemon {

class CameraGate {
  public:
    using Clock = std::chrono::steady_clock;

    explicit CameraGate(const config::CameraConfig& config);

    // Empty when a command may go now (its token is spent); else the
    // kTooManyRequests error naming the limit and when to try again.
    std::optional<CommandError> admit(Clock::time_point now = Clock::now());
    // Logs one sent command of `kind` ("photo", "record toggle"), paced.
    void sent(spdlog::logger& log, std::string_view kind, int pid,
              Clock::time_point now = Clock::now());

    void reload(const config::CameraConfig& config);
    CameraStatus status() const;

    // kInvalidParams when a request asks for on or off while the state is
    // unknown, without force.
    std::optional<CommandError> check_record(const RecordRequest& request) const;
    // Whether the toggle must be sent: not when the state asked for already
    // holds (without force).
    bool toggle_needed(const RecordRequest& request) const;
    // The toggle was sent: the state it led to.
    RecordingState toggled(const RecordRequest& request);
    RecordingState recording() const { return recording_; }
    void device_opened() { recording_ = RecordingState::kUnknown; }

  private:
    base::TokenBucket rate_;
    std::uint64_t refused_ = 0;
    base::RepeatLimiter photo_log_;
    base::RepeatLimiter record_log_;
    RecordingState recording_ = RecordingState::kUnknown;
};

}  // namespace gport::daemon
