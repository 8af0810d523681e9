// VehicleTrack: the vehicle's state checked, and carried to a capture's
// instant (docs/api.md, "The vehicle").
#include "gport/daemon/core/vehicle_track.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

namespace gport::daemon {
namespace {

using std::chrono::milliseconds;

constexpr double kMetresPerDegree = 6378137.0 * std::numbers::pi / 180.0;
const SteadyTime t0{std::chrono::seconds(1000)};
// 2026-11-29T00:00:00Z
constexpr std::int64_t kUtc = 1795910400LL * 1000000;

ClientInfo client(std::uint64_t id) {
    ClientInfo c;
    c.id = id;
    c.pid = static_cast<pid_t>(100 + id);
    c.uid = 1000;
    return c;
}

VehiclePosition north(std::uint32_t boot_ms, double speed = 15.0) {
    VehiclePosition p;
    p.boot_ms = boot_ms;
    p.lat_deg = 47.0;
    p.lon_deg = 8.0;
    p.alt_msl_m = 500.0;
    p.alt_rel_m = 50.0;
    p.velocity_ned = {speed, 0.0, 0.0};
    p.heading_deg = 0.0;
    p.fix = 3;
    p.h_acc_m = 0.5;
    p.v_acc_m = 0.8;
    return p;
}

VehicleReport report(VehiclePosition p) {
    return VehicleReport{p, std::nullopt};
}

class VehicleTrackTest : public ::testing::Test {
  protected:
    config::CameraConfig config;
    VehicleTrack track{config};
};

TEST(VehicleTrackCheck, RefusesValuesOutOfRangeNamingTheFieldAndTheRange) {
    auto p = north(1000);
    p.lat_deg = std::numeric_limits<double>::quiet_NaN();
    auto error = VehicleTrack::check(report(p));
    ASSERT_TRUE(error);
    EXPECT_EQ(error->code, ErrorCode::kInvalidParams);
    EXPECT_NE(error->message.find("position.lat must be a number from -90 to 90"),
              std::string::npos)
        << error->message;

    p = north(1000);
    p.velocity_ned[2] = 1e6;
    error = VehicleTrack::check(report(p));
    ASSERT_TRUE(error);
    EXPECT_NE(error->message.find("velocity_ned[2]"), std::string::npos) << error->message;

    p = north(1000);
    p.fix = 9;
    ASSERT_TRUE(VehicleTrack::check(report(p)));
    EXPECT_TRUE(VehicleTrack::check(VehicleReport{}));
}

TEST(VehicleTrackCheck, RefusesAZeroSystemTimeSayingWhy) {
    const auto error = VehicleTrack::check(VehicleReport{std::nullopt, VehicleTime{1000, 0}});
    ASSERT_TRUE(error);
    EXPECT_NE(error->message.find("time.utc_us"), std::string::npos) << error->message;
    EXPECT_NE(error->message.find("without GPS time"), std::string::npos) << error->message;
    EXPECT_FALSE(VehicleTrack::check(VehicleReport{std::nullopt, VehicleTime{1000, kUtc}}));
}

TEST_F(VehicleTrackTest, NothingPublishedIsNoStampAtAll) {
    EXPECT_FALSE(track.at(t0));
    EXPECT_FALSE(track.status(t0));
}

TEST_F(VehicleTrackTest, CarriesThePositionWithItsVelocityAndGrowsTheAccuracy) {
    ASSERT_FALSE(track.publish(client(1), report(north(1000)), t0));
    const auto stamp = track.at(t0 + milliseconds(200));
    ASSERT_TRUE(stamp);
    ASSERT_TRUE(stamp->tagged) << stamp->why;
    EXPECT_NEAR((stamp->lat_deg - 47.0) * kMetresPerDegree, 3.0, 0.001);
    EXPECT_NEAR(stamp->lon_deg, 8.0, 1e-9);
    EXPECT_EQ(stamp->age, milliseconds(200));
    ASSERT_TRUE(stamp->h_acc_m);
    EXPECT_NEAR(*stamp->h_acc_m, 0.5 + 0.2 * 15.0, 1e-9);
    EXPECT_NEAR(*stamp->v_acc_m, 0.8, 1e-9);
    EXPECT_NEAR(*stamp->alt_rel_m, 50.0, 1e-9);
}

TEST_F(VehicleTrackTest, CarriesOnAnArcWhenTheYawRateIsKnown) {
    auto p = north(1000);
    p.yaw_rate_dps = 30.0;  // turning right, at 15 m/s: a 28.6 m radius
    ASSERT_FALSE(track.publish(client(1), report(p), t0));
    const auto stamp = track.at(t0 + milliseconds(500));
    ASSERT_TRUE(stamp && stamp->tagged);
    const double w = 30.0 * std::numbers::pi / 180.0;
    const double r = 15.0 / w;
    const double north_m = (stamp->lat_deg - 47.0) * kMetresPerDegree;
    const double east_m =
        (stamp->lon_deg - 8.0) * kMetresPerDegree * std::cos(47.0 * std::numbers::pi / 180.0);
    EXPECT_NEAR(north_m, r * std::sin(w * 0.5), 0.001);
    EXPECT_NEAR(east_m, r * (1 - std::cos(w * 0.5)), 0.001);
    EXPECT_NEAR(*stamp->heading_deg, 15.0, 1e-9);
}

// At a pole a metre east is many degrees of longitude: a carry there still
// gives a longitude from -180 to 180 (once it came out as 2335, and
// CAMERA_IMAGE_CAPTURED's degE7 overflowed).
TEST_F(VehicleTrackTest, ACarryAtAPoleKeepsTheLongitudeInRange) {
    for (const double lat : {90.0, -89.99999, 89.9999}) {
        auto p = north(1000);
        p.lat_deg = lat;
        p.lon_deg = 179.0;
        p.velocity_ned = {0.0, 300.0, 0.0};
        VehicleTrack pole{config};
        ASSERT_FALSE(pole.publish(client(1), report(p), t0));
        const auto stamp = pole.at(t0 + milliseconds(900));
        ASSERT_TRUE(stamp && stamp->tagged);
        EXPECT_GE(stamp->lon_deg, -180.0) << lat;
        EXPECT_LE(stamp->lon_deg, 180.0) << lat;
    }
}

TEST_F(VehicleTrackTest, APositionTooOldOrWithoutAFixIsUntaggedNeverStale) {
    ASSERT_FALSE(track.publish(client(1), report(north(1000)), t0));
    auto stamp = track.at(t0 + milliseconds(1500));
    ASSERT_TRUE(stamp);
    EXPECT_FALSE(stamp->tagged);
    EXPECT_NE(stamp->why.find("camera.max_position_age_ms is 1000"), std::string::npos)
        << stamp->why;

    auto p = north(1200);
    p.fix = 1;
    ASSERT_FALSE(track.publish(client(1), report(p), t0 + milliseconds(200)));
    stamp = track.at(t0 + milliseconds(250));
    ASSERT_TRUE(stamp);
    EXPECT_FALSE(stamp->tagged);
    EXPECT_EQ(stamp->why, "no 3D GPS fix (GPS_FIX_TYPE 1)");
}

TEST_F(VehicleTrackTest, RefusesASampleOutOfOrderAndStartsAgainWhenTheAutopilotRebooted) {
    ASSERT_FALSE(track.publish(client(1), report(north(60000)), t0));
    auto error = track.publish(client(1), report(north(59900)), t0 + milliseconds(10));
    ASSERT_TRUE(error);
    EXPECT_EQ(error->code, ErrorCode::kInvalidParams);
    EXPECT_NE(error->message.find("out of order"), std::string::npos) << error->message;
    error = track.publish(client(1), report(north(60000)), t0 + milliseconds(10));
    ASSERT_TRUE(error) << "a repeated boot time";

    // A boot time far behind: the autopilot started again.
    ASSERT_FALSE(track.publish(client(1), report(north(3000)), t0 + milliseconds(20)));
    const auto status = track.status(t0 + milliseconds(20));
    ASSERT_TRUE(status);
    EXPECT_EQ(status->resets, 1u);
    EXPECT_EQ(status->refused, 2u);
    EXPECT_EQ(status->published, 2u);
    const auto stamp = track.at(t0 + milliseconds(120));
    ASSERT_TRUE(stamp && stamp->tagged) << stamp->why;
    EXPECT_EQ(stamp->age, milliseconds(100));
}

// An autopilot that rebooted 4 s after its boot (a brown-out loop): its
// first samples' boot times are not 1000 ms behind the last one taken, but
// they arrive seconds after the clock mapping puts them. The track starts
// again instead of refusing them, and then mapping UTC a reboot late.
TEST_F(VehicleTrackTest, AQuickRebootIsSeenByTheClockMappingAndStartsAgain) {
    ASSERT_FALSE(track.publish(client(1), report(north(4000)), t0));
    const auto later = t0 + milliseconds(5000);  // rebooted, 3.5 s up again
    ASSERT_FALSE(track.publish(client(1), report(north(3500)), later));
    const auto status = track.status(later);
    ASSERT_TRUE(status);
    EXPECT_EQ(status->resets, 1u);
    EXPECT_EQ(status->refused, 0u);
    const auto stamp = track.at(later + milliseconds(100));
    ASSERT_TRUE(stamp && stamp->tagged) << stamp->why;
    EXPECT_EQ(stamp->age, milliseconds(100)) << "mapped through the new boot, not the old";
    // A sample on time is no reboot.
    ASSERT_FALSE(track.publish(client(1), report(north(3600)), later + milliseconds(100)));
    EXPECT_EQ(track.status(later + milliseconds(100))->resets, 1u);
}

TEST_F(VehicleTrackTest, OneSourceAtATimeUntilItLeavesOrFallsSilent) {
    ASSERT_FALSE(track.publish(client(1), report(north(1000)), t0));
    auto error = track.publish(client(2), report(north(1100)), t0 + milliseconds(100));
    ASSERT_TRUE(error);
    EXPECT_EQ(error->code, ErrorCode::kBusy);
    EXPECT_NE(error->message.find("pid 101"), std::string::npos) << error->message;

    track.client_closed(client(1));
    EXPECT_FALSE(track.publish(client(2), report(north(1100)), t0 + milliseconds(100)));
    // client 2 falls silent: after kSourceSilence another may take over.
    EXPECT_TRUE(track.publish(client(3), report(north(1200)), t0 + milliseconds(1000)));
    EXPECT_FALSE(track.publish(client(3), report(north(4200)),
                               t0 + milliseconds(100) + VehicleTrack::kSourceSilence));
}

TEST_F(VehicleTrackTest, TheLeastDelayedSampleMapsTheAutopilotsClock) {
    ASSERT_FALSE(track.publish(client(1), report(north(1000)), t0));
    // The next one arrives 50 ms later than its boot time says: its own
    // latency, not the clock's; the first still maps boot time 1200 to
    // t0 + 200 (and 0.25 ms: its 250 ms of age counted against it).
    ASSERT_FALSE(track.publish(client(1), report(north(1200)), t0 + milliseconds(250)));
    const auto stamp = track.at(t0 + milliseconds(300));
    ASSERT_TRUE(stamp && stamp->tagged);
    EXPECT_GE(stamp->age, milliseconds(99));
    EXPECT_LE(stamp->age, milliseconds(100));
}

// An autopilot whose clock runs 300 ppm slow (as SITL's did under load),
// every sample 2 ms in transit: without the aging the least delayed sample
// of 30 s is the oldest, and the map lags by 9 ms; with it the newest maps
// the clock (a delay every sample shares cannot be seen: it counts as 0).
TEST_F(VehicleTrackTest, AnAutopilotClockRunningSlowDoesNotMakeTheMapLag) {
    SteadyTime arrived = t0;
    std::uint32_t boot_ms = 0;
    for (int elapsed_ms = 0; elapsed_ms <= 30'000; elapsed_ms += 200) {
        boot_ms = 1000 + static_cast<std::uint32_t>(elapsed_ms * (1 - 300e-6));
        arrived = t0 + milliseconds(elapsed_ms + 2);
        ASSERT_FALSE(track.publish(client(1), report(north(boot_ms)), arrived));
    }
    const auto stamp = track.at(arrived + milliseconds(98));
    ASSERT_TRUE(stamp && stamp->tagged);
    // 98 ms after it arrived, 1 ms of rounding either way.
    EXPECT_GE(stamp->age, milliseconds(97));
    EXPECT_LE(stamp->age, milliseconds(99)) << "a plain window would say 107 ms";
}

TEST_F(VehicleTrackTest, UtcIsTheAutopilotsAtTheInstantWhateverTheCompanionsClock) {
    ASSERT_FALSE(track.publish(client(1), VehicleReport{north(1000), VehicleTime{1000, kUtc}}, t0));
    auto stamp = track.at(t0 + milliseconds(300));
    ASSERT_TRUE(stamp && stamp->utc_us);
    EXPECT_EQ(*stamp->utc_us, kUtc + 300000);

    // One wrong SYSTEM_TIME among three moves nothing (the median of the offsets).
    ASSERT_FALSE(track.publish(client(1),
                               VehicleReport{std::nullopt, VehicleTime{2000, kUtc + 1000000}},
                               t0 + milliseconds(1000)));
    ASSERT_FALSE(track.publish(client(1),
                               VehicleReport{std::nullopt, VehicleTime{3000, kUtc + 9000000000}},
                               t0 + milliseconds(2000)));
    stamp = track.at(t0 + milliseconds(2500));
    ASSERT_TRUE(stamp && stamp->utc_us);
    EXPECT_EQ(*stamp->utc_us, kUtc + 2500000);
    EXPECT_FALSE(stamp->tagged) << "the position is 2.5 s old";
}

TEST_F(VehicleTrackTest, StatusShowsTheSourceTheNewestPositionAndItsAge) {
    ASSERT_FALSE(track.publish(client(1), report(north(1000)), t0));
    auto status = track.status(t0 + milliseconds(400));
    ASSERT_TRUE(status && status->source && status->position);
    EXPECT_EQ(status->source->pid, 101);
    EXPECT_EQ(status->position_age, milliseconds(400));
    EXPECT_FALSE(status->utc_known);
    track.client_closed(client(1));
    status = track.status(t0 + milliseconds(400));
    ASSERT_TRUE(status);
    EXPECT_FALSE(status->source);
}

}  // namespace
}  // namespace gport::daemon
