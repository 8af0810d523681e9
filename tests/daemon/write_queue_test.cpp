// The write queue's order (write_queue.hpp): a stop first, the newest
// position command in the place of the one it replaces, other frames capped.
#include "gport/daemon/core/write_queue.hpp"

#include <gtest/gtest.h>

#include "gport/protocol/messages.hpp"

namespace gport::daemon {
namespace {

namespace gp = gport::protocol;

gp::Frame speed(std::int16_t yaw) {
    return gp::encode(gp::Control::speed_of({0, 0, yaw}));
}

gp::Frame photo() {
    return gp::encode(gp::Camera{gp::CameraAction::kPhoto});
}

// A keepalive refreshing a speed behind camera frames keeps its turn: it
// replaces the waiting speed where it waits, instead of going back to the
// end of the line each time (under a flood it was then never sent).
TEST(WriteQueue, ANewerSpeedTakesTheWaitingOnesPlaceInLine) {
    WriteQueue queue(64);
    ASSERT_TRUE(queue.push(photo(), FrameKind::kOther));
    ASSERT_TRUE(queue.push(speed(100), FrameKind::kMotion));
    for (int i = 0; i < 10; ++i) {
        ASSERT_TRUE(queue.push(photo(), FrameKind::kOther));
        ASSERT_TRUE(queue.push(speed(static_cast<std::int16_t>(200 + i)), FrameKind::kMotion));
    }
    EXPECT_EQ(queue.pop().kind, FrameKind::kOther);
    const auto second = queue.pop();
    EXPECT_EQ(second.kind, FrameKind::kMotion) << "second in line, as the first speed was";
    EXPECT_EQ(second.frame, speed(209)) << "the newest speed";
    EXPECT_EQ(queue.replaced(), 10u);
    for (int i = 0; i < 10; ++i) {
        EXPECT_EQ(queue.pop().kind, FrameKind::kOther);
    }
    EXPECT_TRUE(queue.empty());
}

TEST(WriteQueue, AStopGoesFirstAndDropsTheWaitingSpeed) {
    WriteQueue queue(64);
    ASSERT_TRUE(queue.push(photo(), FrameKind::kOther));
    ASSERT_TRUE(queue.push(speed(100), FrameKind::kMotion));
    ASSERT_TRUE(queue.push(speed(0), FrameKind::kStop));
    ASSERT_TRUE(queue.push(speed(0), FrameKind::kStop));
    EXPECT_EQ(queue.pop().kind, FrameKind::kStop);
    EXPECT_EQ(queue.pop().kind, FrameKind::kOther);
    EXPECT_TRUE(queue.empty());
}

TEST(WriteQueue, OtherFramesAreCappedStopsAndSpeedsNever) {
    WriteQueue queue(3);
    for (int i = 0; i < 3; ++i) {
        ASSERT_TRUE(queue.push(photo(), FrameKind::kOther));
    }
    EXPECT_FALSE(queue.push(photo(), FrameKind::kOther));
    EXPECT_EQ(queue.refused(), 1u);
    EXPECT_TRUE(queue.push(speed(5), FrameKind::kMotion));
    EXPECT_TRUE(queue.push(speed(0), FrameKind::kStop));
}

}  // namespace
}  // namespace gport::daemon
