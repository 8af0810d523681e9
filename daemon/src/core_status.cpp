// Core::status(): the figures of every part, gathered for the client API.
#include "gport/daemon/core.hpp"

namespace gport::daemon {

Status Core::status() const {
    Status s;
    link_.report(s);
    const auto now = std::chrono::steady_clock::now();
    s.uptime = std::chrono::duration_cast<Millis>(now - started_);
    if (latest_) {
        s.attitude_age = std::chrono::duration_cast<Millis>(now - latest_->received);
    }
    auto& c = s.counters;
    c.attitude_frames = seq_;
    c.keepalive_frames = motion_.keepalive_frames();
    c.motion_updates = motion_.updates();
    c.settings_timeouts = settings_.timeouts();
    s.motion = motion_.status();
    s.controller = arbiter_.holder();
    s.recording = camera_.recording();
    s.camera = camera_.status();
    s.vehicle = vehicle_.status(now);
    return s;
}

}  // namespace gport::daemon
