// Names of the core's enums, as they appear in logs and on the client API.
#include "gport/daemon/events.hpp"

namespace gport::daemon {

std::string_view to_string(LinkState state) {
    switch (state) {
        case LinkState::kDown:
            return "down";
        case LinkState::kStale:
            return "stale";
        case LinkState::kUp:
            return "up";
    }
    return "unknown";
}

std::string_view to_string(MotionMode mode) {
    switch (mode) {
        case MotionMode::kSpeed:
            return "speed";
        case MotionMode::kAngle:
            return "angle";
        case MotionMode::kCenter:
            return "center";
        case MotionMode::kLock:
            return "lock";
    }
    return "unknown";
}

std::string_view to_string(MotionChange change) {
    switch (change) {
        case MotionChange::kStarted:
            return "started";
        case MotionChange::kReplaced:
            return "replaced";
        case MotionChange::kEnded:
            return "ended";
    }
    return "unknown";
}

std::string_view to_string(EndReason reason) {
    switch (reason) {
        case EndReason::kDuration:
            return "duration";
        case EndReason::kStop:
            return "stop";
        case EndReason::kOwnerGone:
            return "owner_gone";
        case EndReason::kShutdown:
            return "shutdown";
        case EndReason::kSuperseded:
            return "superseded";
        case EndReason::kLinkDown:
            return "link_down";
    }
    return "unknown";
}

}  // namespace gport::daemon
