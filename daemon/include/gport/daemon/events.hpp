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

#include "gport/protocol/messages.hpp"

namespace gport::daemon {

using SteadyTime = std::chrono::steady_clock::time_point;
using WallTime = std::chrono::system_clock::time_point;
using Millis = std::chrono::milliseconds;

// A connected client, identified by the IPC layer (SO_PEERCRED).
struct ClientInfo {
    std::uint64_t id = 0;  // unique per connection, never reused
    pid_t pid = 0;
    uid_t uid = 0;
    gid_t gid = 0;
};

enum class LinkState { kDown, kStale, kUp };
std::string_view to_string(LinkState state);

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

enum class MotionMode { kSpeed, kAngle, kCenter, kLock };
std::string_view to_string(MotionMode mode);

enum class MotionChange { kStarted, kReplaced, kEnded };
std::string_view to_string(MotionChange change);

// Why a speed motion ended.
enum class EndReason { kDuration, kStop, kOwnerGone, kShutdown, kSuperseded, kLinkDown };
std::string_view to_string(EndReason reason);

struct MotionEvent {
    MotionChange change = MotionChange::kStarted;
    MotionMode mode = MotionMode::kSpeed;
    std::optional<ClientInfo> owner;  // who commanded it
    protocol::Axes speed;             // 0.01°/s, for speed motions
    protocol::Axes angle;             // 0.01°, for angle motions
    Millis duration{0};               // asked duration of a speed motion
    std::optional<EndReason> reason;  // set when change == kEnded
};

// Implemented by whoever listens to the core. Called on the event loop.
class CoreObserver {
  public:
    virtual ~CoreObserver() = default;
    virtual void on_attitude(const AttitudeSample& sample) = 0;
    virtual void on_link(const LinkEvent& event) = 0;
    virtual void on_motion(const MotionEvent& event) = 0;
};

}  // namespace gport::daemon
