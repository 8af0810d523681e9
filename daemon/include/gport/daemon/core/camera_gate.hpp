// The camera commands (photo, record), once Core admitted their client
// (access and control, the device): what they must pass before their frame
// goes to the gimbal, a rate a camera can follow (config camera.max_commands_per_s, over all
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
#include <functional>
#include <memory>
#include <optional>
#include <string_view>

#include "gport/base/repeat_limiter.hpp"
#include "gport/base/token_bucket.hpp"
#include "gport/config/config.hpp"
#include "gport/daemon/api.hpp"
#include "gport/daemon/outcome.hpp"
#include "gport/protocol/messages.hpp"

namespace gport::daemon {

class CameraGate {
  public:
    using Clock = std::chrono::steady_clock;

    // Queues a frame for the device; the error when it could not be queued.
    using Send = std::function<std::optional<CommandError>(const protocol::Frame&)>;

    CameraGate(const config::CameraConfig& config, std::shared_ptr<spdlog::logger> log, Send send);

    // A photo for client `pid`: the rate, then the frame.
    Outcome<Done> photo(int pid);
    // A record request that passed check_record(): the toggle when the state
    // asked for does not hold already (or with force), then the state.
    Outcome<RecordResult> record(const RecordRequest& request, int pid);

    // Empty when a command may go now (its token is spent); else the
    // kTooManyRequests error naming the limit and when to try again.
    std::optional<CommandError> admit(Clock::time_point now = Clock::now());

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
    Outcome<Done> command(protocol::CameraAction action, int pid);
    // Logs one sent command of `kind` ("photo", "record toggle"), paced.
    void sent(std::string_view kind, int pid, Clock::time_point now = Clock::now());

    std::shared_ptr<spdlog::logger> log_;
    Send send_;
    base::TokenBucket rate_;
    std::uint64_t refused_ = 0;
    base::RepeatLimiter photo_log_;
    base::RepeatLimiter record_log_;
    RecordingState recording_ = RecordingState::kUnknown;
};

}  // namespace gport::daemon
