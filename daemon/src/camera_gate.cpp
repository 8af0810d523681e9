#include "gport/daemon/core/camera_gate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <utility>

namespace gport::daemon {

namespace {

using namespace std::chrono_literals;

constexpr auto kLogInterval = 10s;

std::optional<RecordingState> wanted(const RecordRequest& request) {
    if (!request.on) {
        return std::nullopt;
    }
    return *request.on ? RecordingState::kOn : RecordingState::kOff;
}

base::TokenBucket bucket(const config::CameraConfig& config) {
    // A burst of one second's worth, and at least one command.
    return base::TokenBucket(config.max_commands_per_s, std::max(1.0, config.max_commands_per_s));
}

}  // namespace

CameraGate::CameraGate(const config::CameraConfig& config, std::shared_ptr<spdlog::logger> log,
                       Send send)
    : log_(std::move(log)),
      send_(std::move(send)),
      rate_(bucket(config)),
      photo_log_(kLogInterval),
      record_log_(kLogInterval) {}

Outcome<Done> CameraGate::photo(int pid) {
    return command(protocol::CameraAction::kPhoto, pid);
}

Outcome<RecordResult> CameraGate::record(const RecordRequest& request, int pid) {
    if (!toggle_needed(request)) {
        return RecordResult{false, recording_};
    }
    if (auto done = command(protocol::CameraAction::kToggleRecording, pid); !done) {
        return done.error();
    }
    log_->info("recording assumed {}", to_string(toggled(request)));
    return RecordResult{true, recording_};
}

Outcome<Done> CameraGate::command(protocol::CameraAction action, int pid) {
    if (auto refused = admit()) {
        return std::move(*refused);
    }
    if (auto failed = send_(protocol::encode(protocol::Camera{action}))) {
        return std::move(*failed);
    }
    sent(action == protocol::CameraAction::kPhoto ? "photo" : "record toggle", pid);
    return Done{};
}

std::optional<CommandError> CameraGate::admit(Clock::time_point now) {
    if (rate_.take(now)) {
        return std::nullopt;
    }
    ++refused_;
    const auto wait = std::chrono::ceil<std::chrono::milliseconds>(rate_.wait_for(now));
    return CommandError{
        ErrorCode::kTooManyRequests,
        fmt::format("too many camera commands: the limit is {:g} per second over all clients "
                    "(camera.max_commands_per_s), what a camera can follow; nothing was sent; "
                    "try again in {} ms",
                    rate_.rate(), wait.count())};
}

void CameraGate::sent(std::string_view kind, int pid, Clock::time_point now) {
    auto& limiter = kind == "photo" ? photo_log_ : record_log_;
    if (auto count = limiter.occur(now)) {
        if (*count == 1) {
            log_->info("camera {} by pid {}", kind, pid);
        } else {
            log_->info("camera {} by pid {} ({} {} commands in the last {} s)", kind, pid, *count,
                       kind,
                       std::chrono::duration_cast<std::chrono::seconds>(kLogInterval).count());
        }
    }
}

void CameraGate::reload(const config::CameraConfig& config) {
    if (config.max_commands_per_s != rate_.rate()) {
        rate_ = bucket(config);
    }
}

CameraStatus CameraGate::status() const {
    return CameraStatus{rate_.rate(), refused_};
}

std::optional<CommandError> CameraGate::check_record(const RecordRequest& request) const {
    if (!request.on || recording_ != RecordingState::kUnknown || request.force) {
        return std::nullopt;
    }
    return CommandError{
        ErrorCode::kInvalidParams,
        fmt::format("the recording state is unknown (gportd cannot read it from the gimbal, "
                    "and forgets it when the device reopens); send record "
                    "{{\"on\": {}, \"force\": true}} to toggle anyway and take {} as the "
                    "new state",
                    *request.on, *request.on ? "on" : "off")};
}

bool CameraGate::toggle_needed(const RecordRequest& request) const {
    return request.force || wanted(request) != recording_;
}

RecordingState CameraGate::toggled(const RecordRequest& request) {
    if (auto state = wanted(request)) {
        recording_ = *state;
    } else if (recording_ != RecordingState::kUnknown) {
        recording_ = recording_ == RecordingState::kOn ? RecordingState::kOff : RecordingState::kOn;
    }
    return recording_;
}

}  // namespace gport::daemon
