// A MonitorModel as a running gimbal gives it, for the renderer's tests.
#pragma once

#include "state.hpp"

namespace gport::cli::monitor::testing {

inline MonitorModel running_model() {
    MonitorModel m;
    m.socket = "/run/gportd.sock";
    m.clock = "12:03:04";
    m.connected = true;
    m.daemon_version = "0.1.0";
    m.uptime_ms = 3'723'000;
    m.link_state = "up";
    m.link_reason = "attitude arriving";
    m.device = "/dev/gimbal";
    m.device_open = true;
    m.attitude_age_ms = 12;
    client::AttitudeSample sample;
    sample.seq = 1042;
    sample.imu = {.roll = 12.34, .pitch = -30.0, .yaw = 45.0};
    sample.hall = {.roll = 12.3, .pitch = -29.9, .yaw = 44.8};
    m.attitude = sample;
    m.motion = MotionView{.mode = "speed",
                          .owner = "pid 812 (client 4)",
                          .speed = client::Axes{.roll = 0, .pitch = 0, .yaw = 30},
                          .target = std::nullopt,
                          .time_left_ms = 1400,
                          .elapsed_ms = 600};
    m.last_end = MotionEnd{.mode = "angle", .reason = "reached", .clock = "12:02:58"};
    m.controller = "free";
    client::Counters counters;
    counters.attitude_frames = 186'150;
    counters.crc_errors = 3;
    counters.resyncs = 1;
    m.counters = counters;
    m.frame_rate_hz = 50;
    m.clients = 3;
    m.dropped_total = 7;
    m.dropped_self = 2;
    m.recording = "unknown";
    m.events = {{"12:02:50", "connected to gportd at /run/gportd.sock", Severity::kGood},
                {"12:02:50", "link up: attitude arriving", Severity::kGood},
                {"12:02:58", "angle ended: reached", Severity::kInfo},
                {"12:03:03", "speed started by pid 812 (client 4): yaw +30.0 °/s for 2.0 s",
                 Severity::kGood}};
    m.events_total = 4;
    return m;
}

}  // namespace gport::cli::monitor::testing
