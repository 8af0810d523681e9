// The daemon core's narrow face towards its users (the IPC layer, systemd
// status, tests): who a client is, and the events the core publishes. No
// JSON and no sockets here.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gport/protocol/messages.hpp"

namespace gport::daemon {

using SteadyTime = std::chrono::steady_clock::time_point;
using WallTime = std::chrono::system_clock::time_point;
using Millis = std::chrono::milliseconds;

// A connected client, identified by the IPC layer (SO_PEERCRED and
// SO_PEERGROUPS: the credentials the peer process had when it connected).
struct ClientInfo {
    std::uint64_t id = 0;  // unique per connection, never reused
    pid_t pid = 0;
    uid_t uid = 0;
    gid_t gid = 0;
    std::vector<gid_t> groups;  // the peer's supplementary groups
};

enum class LinkState { kDown, kStale, kUp };

// One 0x87 frame as received.
struct AttitudeSample {
    std::uint64_t seq = 0;  // 1 for the first frame since start, never reset
    WallTime wall{};        // receive time, for clients ("t")
    SteadyTime received{};  // receive time, for ages
    protocol::Attitude attitude;
};

struct LinkEvent {
    LinkState state = LinkState::kDown;
    std::string reason;
};

// A motion's mode is the mode of the 0x85 control frame that started it:
// one enum (the wire's) and one to_string, protocol::to_string(ControlMode).
using MotionMode = protocol::ControlMode;
using protocol::to_string;

// kUpdated: the owner of a speed motion sent another speed (a streaming
// controller); published at most once per kUpdateNoteInterval, the latest
// speed winning.
enum class MotionChange { kStarted, kReplaced, kEnded, kUpdated };

// Why a motion ended. Speed motions end with the first eight; tracked angle
// and centre motions (MotionTracker) with kReached, kTimeout, kStalled, kReplaced (a
// newer angle or centre), kStop, kOwnerGone (only a waiting owner),
// kSuperseded (a speed or lock), kPreempted, kLinkDown or kShutdown.
enum class EndReason {
    kDuration,
    kStop,
    kOwnerGone,
    kShutdown,
    kSuperseded,
    kLinkDown,
    kPreempted,     // another client acquired control
    kLeaseExpired,  // no update from its owner within the lease
    kReached,       // every axis within motion.tolerance_deg of its target, twice running
    kTimeout,       // not reached within motion.timeout_ms
    kStalled,       // no progress towards the target for motion.stall_ms
    kReplaced,      // a newer angle or centre command
    kLimit,         // every moving axis was braked at its soft limit
    kNoAttitude,    // no fresh attitude to brake by while a soft limit applies
};

struct MotionEvent {
    MotionChange change = MotionChange::kStarted;
    MotionMode mode = MotionMode::kSpeed;
    std::optional<ClientInfo> owner;   // who commanded it
    protocol::Axes speed;              // 0.01°/s, for speed motions
    protocol::Axes angle;              // 0.01°, the target of angle (and centre: 0) motions
    Millis duration{0};                // asked duration of a speed motion
    std::optional<EndReason> reason;   // set when change == kEnded; kLimit on a braking kUpdated
    std::vector<std::string> braked;   // reason kLimit: the axes held at zero by the soft limits
    std::vector<std::string> clamped;  // angle and centre: target axes clamped into the limits
    std::string detail{};              // reason kStalled: where the gimbal stopped, else empty
};

// Implemented by whoever listens to the core. Called on the event loop.
class CoreObserver {
  public:
    virtual ~CoreObserver() = default;
    virtual void on_attitude(const AttitudeSample& sample) = 0;
    virtual void on_link(const LinkEvent& event) = 0;
    virtual void on_motion(const MotionEvent& event) = 0;
};

// Names as they appear in logs and on the client API.
constexpr std::string_view to_string(LinkState state) {
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

constexpr std::string_view to_string(MotionChange change) {
    switch (change) {
        case MotionChange::kStarted:
            return "started";
        case MotionChange::kReplaced:
            return "replaced";
        case MotionChange::kEnded:
            return "ended";
        case MotionChange::kUpdated:
            return "updated";
    }
    return "unknown";
}

constexpr std::string_view to_string(EndReason reason) {
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
        case EndReason::kPreempted:
            return "preempted";
        case EndReason::kLeaseExpired:
            return "lease_expired";
        case EndReason::kReached:
            return "reached";
        case EndReason::kTimeout:
            return "timeout";
        case EndReason::kStalled:
            return "stalled";
        case EndReason::kReplaced:
            return "replaced";
        case EndReason::kLimit:
            return "limit";
        case EndReason::kNoAttitude:
            return "no_attitude";
    }
    return "unknown";
}

}  // namespace gport::daemon
