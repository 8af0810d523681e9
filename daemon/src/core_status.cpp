// Core::status(): the figures of every part, gathered for the client API.
#include "gport/daemon/core.hpp"

namespace gport::daemon {

Status Core::status() const {
    Status s;
    s.link = monitor_.state();
    s.link_reason = monitor_.reason();
    s.device = config_.serial.device;
    s.device_open = port_.is_open();
    if (!s.device_open && !port_.open_error().empty()) {
        s.device_error = port_.open_error();
    }
    const auto now = std::chrono::steady_clock::now();
    s.uptime = std::chrono::duration_cast<Millis>(now - started_);
    if (latest_) {
        s.attitude_age = std::chrono::duration_cast<Millis>(now - latest_->received);
    }
    const auto& d = reader_.stats();
    const auto& l = port_.stats();
    auto& c = s.counters;
    c.frames_in = d.frames;
    c.bytes_in = d.bytes;
    c.frames_out = l.frames_out;
    c.bytes_out = l.bytes_out;
    c.attitude_frames = seq_;
    c.crc_errors = d.crc_errors;
    c.header_errors = d.header_errors;
    c.garbage_bytes = d.garbage_bytes;
    c.resyncs = d.resyncs;
    c.bad_messages = reader_.bad_messages();
    c.device_opens = l.opens;
    c.device_failures = l.failures;
    c.keepalive_frames = motion_.keepalive_frames();
    c.motion_updates = motion_.updates();
    c.stops_sent = l.stops_written;
    c.frames_replaced = l.frames_replaced;
    c.frames_refused = l.queue_overflows;
    c.settings_timeouts = settings_.timeouts();
    s.motion = motion_.status();
    s.controller = arbiter_.holder();
    s.recording = camera_.recording();
    s.camera = camera_.status();
    return s;
}

}  // namespace gport::daemon
