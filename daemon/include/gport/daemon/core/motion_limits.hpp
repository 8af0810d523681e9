// Soft limits on motion (docs/configuration.md, "limits"): the angle range of
// each axis and the fastest speed on any axis. The core applies them to every
// client's angle and speed commands: beyond a limit, a command is refused
// (kInvalidParams) or, when the client asks, clamped into range. Pure: no
// state beyond the configuration, so it is cheap to build per command.
#pragma once

#include <string>
#include <vector>

#include "gport/config/config.hpp"
#include "gport/daemon/outcome.hpp"
#include "gport/protocol/messages.hpp"

namespace gport::daemon {

// What a command sends after the limits, and which axes were clamped
// ("roll", "pitch", "yaw" in that order).
struct Limited {
    protocol::Axes axes;
    std::vector<std::string> clamped;
};

class MotionLimits {
  public:
    explicit MotionLimits(const config::LimitsConfig& config) : config_(config) {}

    // Angles in 0.01°. Without `clamp`, a target outside its axis's range is
    // refused naming the axis, the value and the range; with it, each axis
    // is clamped into its range.
    Outcome<Limited> angle(protocol::Axes target, bool clamp) const;
    // 0/0/0 clamped into the angle ranges: the centre that `center` and the
    // failsafe aim at (docs/api.md, "center and the soft limits").
    Limited center_target() const;
    // Speeds in 0.01°/s, the same for |speed| above limits.max_speed.
    Outcome<Limited> speed(protocol::Axes speed, bool clamp) const;

  private:
    config::LimitsConfig config_;
};

}  // namespace gport::daemon
