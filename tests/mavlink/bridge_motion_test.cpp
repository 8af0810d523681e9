// The vehicle's yaw for earth-frame targets (vehicle_yaw.hpp) and the lease
// of rate commands (rate_lease.hpp), issue 31.
#include <gtest/gtest.h>

#include <chrono>

#include "gport/mavlink/bridge/rate_lease.hpp"
#include "gport/mavlink/bridge/vehicle_yaw.hpp"

namespace gport::mavlink::bridge {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

TEST(VehicleYaw, NoneWithoutAReading) {
    VehicleYaw yaw;
    EXPECT_FALSE(yaw.at(Clock::now()));
    EXPECT_EQ(yaw.source(Clock::now()), YawSource::kNone);
    EXPECT_EQ(to_string(YawSource::kNone), "none");
}

// PX4's Onboard link: ATTITUDE, no AUTOPILOT_STATE_FOR_GIMBAL_DEVICE.
TEST(VehicleYaw, AttitudeAloneServesWhileFresh) {
    VehicleYaw yaw;
    const auto t0 = Clock::now();
    yaw.from_attitude(42.5, 3.0, t0);
    const auto reading = yaw.at(t0 + 900ms);
    ASSERT_TRUE(reading);
    EXPECT_EQ(reading->yaw_deg, 42.5);
    EXPECT_EQ(reading->rate_dps, 3.0);
    EXPECT_EQ(reading->source, YawSource::kAttitude);
    EXPECT_EQ(to_string(reading->source), "ATTITUDE");
    EXPECT_FALSE(yaw.at(t0 + VehicleYaw::kMaxAge));
}

TEST(VehicleYaw, AutopilotStateWinsWhileFreshThenAttitude) {
    VehicleYaw yaw;
    const auto t0 = Clock::now();
    yaw.from_autopilot_state(10, std::nullopt, t0);
    yaw.from_attitude(11, std::nullopt, t0 + 500ms);
    EXPECT_EQ(yaw.at(t0 + 600ms)->yaw_deg, 10);
    EXPECT_EQ(yaw.source(t0 + 600ms), YawSource::kAutopilotState);
    EXPECT_EQ(yaw.at(t0 + 1200ms)->yaw_deg, 11);  // the state is stale, ATTITUDE is not
    EXPECT_EQ(yaw.source(t0 + 1200ms), YawSource::kAttitude);
    EXPECT_EQ(yaw.source(t0 + 1600ms), YawSource::kNone);
}

TEST(RateLease, AFastStreamKeepsTheFloor) {
    RateLease lease(500ms);
    auto t = Clock::now();
    for (int i = 0; i < 10; ++i, t += 20ms) {
        EXPECT_EQ(lease.on_message(t), 500ms);
    }
}

// PX4's Onboard link: SET_ATTITUDE about every 1.7 s (36 in 60 s, jittery).
TEST(RateLease, ASlowStreamGetsOneAndAHalfItsLongestInterval) {
    RateLease lease(500ms);
    auto t = Clock::now();
    EXPECT_EQ(lease.on_message(t), 500ms);
    EXPECT_EQ(lease.on_message(t += 1700ms), 2550ms);
    EXPECT_EQ(lease.on_message(t += 1400ms), 2550ms);
    EXPECT_EQ(lease.on_message(t += 2000ms), 3000ms);
    // Once the longest has left the last 4, the lease follows the link down.
    for (int i = 0; i < 4; ++i) {
        lease.on_message(t += 100ms);
    }
    EXPECT_EQ(lease.current(), 500ms);
}

// PX4's Onboard link (SITL, issue 31): the manager streams angles (or its
// all-NaN idle messages) about every 1.7 s before the first rate; that
// rate's lease covers the 1.7 s to the next message, so the gimbal does
// not stop after --lease-ms and wait for it.
TEST(RateLease, TheMessagesBeforeTheFirstRateSetItsLease) {
    RateLease lease(500ms);
    auto t = Clock::now();
    lease.on_message(t);                               // an angle
    lease.on_message(t += 1700ms);                     // an angle
    EXPECT_EQ(lease.on_message(t += 1650ms), 2550ms);  // the first rate
}

TEST(RateLease, APauseIsANewStreamAndTheCeilingHolds) {
    RateLease lease(500ms);
    auto t = Clock::now();
    lease.on_message(t);
    EXPECT_EQ(lease.on_message(t += 30s), 500ms);  // a pause: not counted
    EXPECT_EQ(lease.on_message(t += 4500ms), RateLease::kDefaultCeiling);
    lease.set_ceiling(2000ms);  // gportd's keepalive.max_duration_ms
    EXPECT_EQ(lease.current(), 2000ms);
    lease.set_ceiling(300ms);  // below the floor: the ceiling wins
    EXPECT_EQ(lease.current(), 300ms);
}

// PX4's Onboard link (SITL, issue 31): a lease of 2.55 s with gportd's
// default duration (1 s) moved the gimbal 1 s of every 1.7 s.
TEST(RateLease, TheDurationIsTheLease) {
    const auto options = speed_options(2550ms);
    EXPECT_EQ(options.lease, 2550ms);
    EXPECT_EQ(options.duration, 2550ms);
    EXPECT_FALSE(options.clamp);
}

TEST(RateLease, GportdsLimitIsReadFromItsRefusal) {
    EXPECT_EQ(max_lease_in("lease_ms must be an integer from 1 to 2000 "
                           "(keepalive.max_duration_ms)"),
              2000ms);
    // The duration is checked first and bounded by the same maximum.
    EXPECT_EQ(max_lease_in("duration_ms must be an integer from 1 to 1500 "
                           "(keepalive.max_duration_ms)"),
              1500ms);
    EXPECT_FALSE(max_lease_in("roll_ms must be an integer from 1 to 1500"));
    EXPECT_FALSE(max_lease_in("yaw = 80 °/s is faster than the soft limit"));
    EXPECT_FALSE(max_lease_in("lease_ms must be an integer from 1 to x"));
}

}  // namespace
}  // namespace gport::mavlink::bridge
