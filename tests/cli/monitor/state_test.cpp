// MonitorState: notifications, statuses and the monitor's own doings become
// the model a frame shows, with ages and time left for a given moment.
#include "state.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace gport::cli::monitor {
namespace {

using namespace std::chrono_literals;
using ::testing::HasSubstr;

const SteadyTime kStart{};

Now at(std::chrono::milliseconds offset) {
    return Now{kStart + offset, "12:00:00"};
}

client::Status status_with(std::int64_t self_id) {
    client::Status s;
    s.daemon_version = "0.1.0";
    s.link = {.state = "up", .reason = "attitude arriving"};
    s.device = "/dev/gimbal";
    s.device_open = true;
    s.uptime_ms = 5000;
    s.attitude_age_ms = 4;
    s.self.id = self_id;
    return s;
}

client::MotionEvent speed_started() {
    client::MotionEvent e{.change = "started", .mode = "speed"};
    e.owner = client::Peer{.id = 4, .pid = 812};
    e.speed = client::Axes{.yaw = 30};
    e.duration_ms = 2000;
    return e;
}

TEST(MonitorState, SpeedMotionCountsDownThenEndsWithItsReason) {
    MonitorState state("/s", false);
    state.on_status(status_with(7), at(0ms));
    state.on_notification(speed_started(), at(100ms));
    auto model = state.model(at(600ms));
    ASSERT_TRUE(model.motion);
    EXPECT_EQ(model.motion->mode, "speed");
    EXPECT_EQ(model.motion->owner, "pid 812 (client 4)");
    EXPECT_EQ(model.motion->time_left_ms, 1500);
    EXPECT_EQ(state.model(at(5000ms)).motion->time_left_ms, 0);  // never negative
    EXPECT_THAT(model.events.back().text,
                HasSubstr("speed started by pid 812 (client 4): yaw +30.0 °/s for 2.0 s"));

    client::MotionEvent ended{.change = "ended", .mode = "speed"};
    ended.reason = "duration";
    state.on_notification(ended, Now{kStart + 2100ms, "12:00:02"});
    model = state.model(at(2200ms));
    EXPECT_FALSE(model.motion);
    ASSERT_TRUE(model.last_end);
    EXPECT_EQ(model.last_end->reason, "duration");
    EXPECT_EQ(model.last_end->clock, "12:00:02");
    EXPECT_EQ(model.events.back().text, "speed ended: duration");
}

TEST(MonitorState, OwnMotionAndControlShowAsYou) {
    MonitorState state("/s", true);
    auto status = status_with(4);
    status.controller = client::Peer{.id = 4, .pid = 99};
    status.motion = client::Motion{.mode = "angle"};
    status.motion->owner = client::Peer{.id = 4};
    status.motion->target = client::Axes{.pitch = -30};
    status.motion->elapsed_ms = 400;
    state.on_status(status, at(0ms));
    const auto model = state.model(at(100ms));
    EXPECT_EQ(model.controller, "you");
    EXPECT_TRUE(model.holds_control);
    EXPECT_TRUE(model.control_requested);
    ASSERT_TRUE(model.motion);
    EXPECT_EQ(model.motion->owner, "you");
    EXPECT_EQ(model.motion->elapsed_ms, 500);
}

TEST(MonitorState, LinkChangesAreEventsWithASeverity) {
    MonitorState state("/s", false);
    state.on_status(status_with(1), at(0ms));
    state.on_notification(client::LinkEvent{.state = "down", .reason = "device vanished"},
                          at(10ms));
    const auto model = state.model(at(20ms));
    EXPECT_EQ(model.link_state, "down");
    EXPECT_EQ(model.link_reason, "device vanished");
    EXPECT_EQ(model.events.back().text, "link down: device vanished");
    EXPECT_EQ(model.events.back().severity, Severity::kBad);
    // The same state again is no new event.
    const auto count = model.events_total;
    state.on_notification(client::LinkEvent{.state = "down", .reason = "device vanished"},
                          at(30ms));
    EXPECT_EQ(state.model(at(40ms)).events_total, count);
}

TEST(MonitorState, AttitudeAgeFromTheLastSample) {
    MonitorState state("/s", false);
    state.on_status(status_with(1), at(0ms));
    EXPECT_EQ(state.model(at(100ms)).attitude_age_ms, 104);  // the status's 4 ms, aged
    client::AttitudeSample sample;
    sample.imu.yaw = 12;
    sample.dropped = 3;
    state.on_notification(sample, at(200ms));
    const auto model = state.model(at(250ms));
    EXPECT_EQ(model.attitude_age_ms, 50);
    ASSERT_TRUE(model.attitude);
    EXPECT_EQ(model.attitude->imu.yaw, 12);
    EXPECT_EQ(model.dropped_self, 3u);
}

TEST(MonitorState, FrameRateFromTwoStatuses) {
    MonitorState state("/s", false);
    auto status = status_with(1);
    status.counters.attitude_frames = 1000;
    state.on_status(status, at(0ms));
    EXPECT_FALSE(state.model(at(0ms)).frame_rate_hz);
    status.counters.attitude_frames = 1025;
    state.on_status(status, at(500ms));
    EXPECT_DOUBLE_EQ(*state.model(at(500ms)).frame_rate_hz, 50.0);
}

TEST(MonitorState, DisconnectForgetsTheLinkAndSaysWhy) {
    MonitorState state("/s", false);
    state.on_connected(at(0ms));
    state.on_status(status_with(1), at(0ms));
    state.on_disconnected("the daemon closed the connection", at(10ms));
    const auto model = state.model(at(20ms));
    EXPECT_FALSE(model.connected);
    EXPECT_EQ(model.link_state, "unknown");
    EXPECT_EQ(model.connection_error, "the daemon closed the connection");
    EXPECT_EQ(model.events.back().text,
              "lost the connection to gportd: the daemon closed the connection");
    // The values kept are marked as from before the loss; retries that fail
    // keep that time.
    EXPECT_EQ(model.stale_since, "12:00:00");
    state.on_disconnected("cannot connect", Now{kStart + 2s, "12:00:02"});
    EXPECT_EQ(state.model(at(2s)).stale_since, "12:00:00");
    EXPECT_EQ(state.model(at(2s)).connection_error, "cannot connect");
    state.on_connected(at(3s));
    EXPECT_TRUE(state.model(at(3s)).connected);
    EXPECT_EQ(state.model(at(3s)).stale_since, "");
}

TEST(MonitorState, KeepsTheLatestEvents) {
    MonitorState state("/s", false);
    for (int i = 0; i < 100; ++i) {
        state.note("event " + std::to_string(i), Severity::kInfo, at(0ms));
    }
    const auto model = state.model(at(0ms));
    EXPECT_EQ(model.events.size(), MonitorState::kMaxEvents);
    EXPECT_EQ(model.events.back().text, "event 99");
    EXPECT_EQ(model.events_total, 100u);
}

}  // namespace
}  // namespace gport::cli::monitor
