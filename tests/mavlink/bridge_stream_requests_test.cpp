// Geotag by default (stream_requests.hpp, issue 31 item 4): the autopilot
// is asked for GLOBAL_POSITION_INT and ATTITUDE when they do not come, a
// bounded number of times, and not while they come.
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "gport/mavlink/bridge/stream_requests.hpp"

namespace gport::mavlink::bridge {
namespace {

using namespace std::chrono_literals;
using Clock = StreamRequests::Clock;

constexpr std::uint32_t kPosition = 33;
constexpr std::uint32_t kAttitude = 30;

StreamRequests both() {
    return StreamRequests({{kPosition, 200000}, {kAttitude, 100000}});
}

TEST(StreamRequests, NothingWithoutTheAutopilotsHeartbeat) {
    auto streams = both();
    EXPECT_TRUE(streams.due(Clock::now() + 1h).empty());
}

TEST(StreamRequests, AskedForAfterTheGraceThenBounded) {
    auto streams = both();
    const auto t0 = Clock::now();
    streams.on_heartbeat(t0);
    EXPECT_TRUE(streams.due(t0 + StreamRequests::kGrace - 1ms).empty());
    const auto first = streams.due(t0 + StreamRequests::kGrace);
    ASSERT_EQ(first.size(), 2U);
    EXPECT_EQ(first[0].msgid, kPosition);
    EXPECT_EQ(first[0].interval_us, 200000U);
    EXPECT_EQ(first[1].msgid, kAttitude);
    EXPECT_EQ(streams.attempts(kPosition), 1U);
    // Not again before kRetry; then up to kAttempts in all.
    EXPECT_TRUE(streams.due(t0 + StreamRequests::kGrace + 1s).empty());
    auto t = t0 + StreamRequests::kGrace;
    for (std::uint32_t i = 1; i < StreamRequests::kAttempts; ++i) {
        t += StreamRequests::kRetry;
        EXPECT_EQ(streams.due(t).size(), 2U);
    }
    EXPECT_EQ(streams.attempts(kPosition), StreamRequests::kAttempts);
    EXPECT_TRUE(streams.due(t + 1h).empty());
}

TEST(StreamRequests, AStreamThatComesIsNotAskedFor) {
    auto streams = both();
    const auto t0 = Clock::now();
    streams.on_heartbeat(t0);
    streams.on_message(kAttitude, t0 + 2s);
    const auto due = streams.due(t0 + StreamRequests::kGrace);
    ASSERT_EQ(due.size(), 1U);
    EXPECT_EQ(due[0].msgid, kPosition);
    EXPECT_EQ(streams.attempts(kAttitude), 0U);
}

// Lost later: asked for again, with a fresh count.
TEST(StreamRequests, ALostStreamIsAskedForAgain) {
    auto streams = both();
    const auto t0 = Clock::now();
    streams.on_heartbeat(t0);
    streams.on_message(kAttitude, t0);
    for (int i = 0; i < 3; ++i) {
        streams.due(t0 + StreamRequests::kGrace + i * StreamRequests::kRetry);
    }
    EXPECT_EQ(streams.attempts(kPosition), StreamRequests::kAttempts);
    const auto t1 = t0 + 20s;
    streams.on_message(kPosition, t1);
    streams.on_message(kAttitude, t1);
    EXPECT_EQ(streams.attempts(kPosition), 0U);
    EXPECT_TRUE(streams.due(t1 + 1s).empty());
    const auto again = streams.due(t1 + StreamRequests::kGrace);
    EXPECT_EQ(again.size(), 2U);
}

// Only the streams asked for are requested (the bridge wants four: bridge.cpp).
TEST(StreamRequests, OnlyTheWantedOnes) {
    StreamRequests streams({{kAttitude, 100000}});
    const auto t0 = Clock::now();
    streams.on_heartbeat(t0);
    const auto due = streams.due(t0 + StreamRequests::kGrace);
    ASSERT_EQ(due.size(), 1U);
    EXPECT_EQ(due[0].msgid, kAttitude);
    EXPECT_EQ(streams.attempts(kPosition), 0U);
}

// The warning names each autopilot's remedy; for PX4 the Onboard link,
// not the Gimbal link (which in SITL streamed no position and answered no
// SET_MESSAGE_INTERVAL, issue 31).
TEST(StreamRequests, TheWarningNamesWhatToSet) {
    const std::string asked = no_position_warning(4, 1, 1000ms, 3);
    EXPECT_NE(asked.find("image_index 4 has no position"), std::string::npos) << asked;
    EXPECT_NE(asked.find("system 1 component 1) in the last 1000 ms; asked for it 3 time(s)"),
              std::string::npos)
        << asked;
    EXPECT_NE(asked.find("MAVn_POSITION"), std::string::npos) << asked;
    EXPECT_NE(asked.find("SRn_POSITION"), std::string::npos) << asked;
    EXPECT_NE(asked.find("PX4: an Onboard link (MAV_x_MODE Onboard"), std::string::npos) << asked;
    EXPECT_EQ(asked.find("Onboard or Gimbal"), std::string::npos) << asked;
    EXPECT_EQ(no_position_warning(0, 1, 1000ms, 0).find("asked for it"), std::string::npos);
}

}  // namespace
}  // namespace gport::mavlink::bridge
