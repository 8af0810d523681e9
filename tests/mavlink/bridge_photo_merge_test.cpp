// One command, one photo (photo_merge.hpp, issue 31 item 5): ArduPilot's
// forwarded command and its own command for one photo are one photo; two
// photos asked for apart, or by two ground stations, stay two.
#include <gtest/gtest.h>

#include <chrono>

#include "gport/mavlink/bridge/photo_merge.hpp"

namespace gport::mavlink::bridge {
namespace {

using namespace std::chrono_literals;
using Clock = PhotoMerge::Clock;
using Match = PhotoMerge::Match;

constexpr std::uint8_t kVehicleSysid = 1;
constexpr PhotoMerge::Sender kGroundStation190{255, 190};
constexpr PhotoMerge::Sender kAutopilotSender{1, 1};
constexpr std::uint8_t kResultAccepted = 0;
constexpr std::uint8_t kResultDenied = 4;

TEST(PhotoMerge, NothingBegunIsNew) {
    const PhotoMerge merge;
    EXPECT_EQ(merge.match(kAutopilotSender, kVehicleSysid, Clock::now()), Match::kNew);
    EXPECT_FALSE(merge.result());
}

// ArduPilot: the ground station's command forwarded, then its own 0.3 ms later.
TEST(PhotoMerge, AutopilotsOwnCommandJoinsThePhotoInFlight) {
    PhotoMerge merge;
    const auto t0 = Clock::now();
    merge.begun(kGroundStation190, t0);
    EXPECT_EQ(merge.match(kAutopilotSender, kVehicleSysid, t0 + 300us), Match::kInFlight);
    merge.done(kResultAccepted);
    EXPECT_EQ(merge.match(kAutopilotSender, kVehicleSysid, t0 + 49ms), Match::kDone);
    EXPECT_EQ(merge.result(), kResultAccepted);
    EXPECT_EQ(merge.since_begun(t0 + 49ms), 49ms);
}

// The other order (the autopilot's own first) is the same photo too, and a
// failed photo answers both with its failure.
TEST(PhotoMerge, EitherOrderAndTheResultIsShared) {
    PhotoMerge merge;
    const auto t0 = Clock::now();
    merge.begun(kAutopilotSender, t0);
    merge.done(kResultDenied);
    EXPECT_EQ(merge.match(kGroundStation190, kVehicleSysid, t0 + 1ms), Match::kDone);
    EXPECT_EQ(merge.result(), kResultDenied);
}

TEST(PhotoMerge, PastTheWindowIsANewPhoto) {
    PhotoMerge merge;
    const auto t0 = Clock::now();
    merge.begun(kGroundStation190, t0);
    merge.done(kResultAccepted);
    EXPECT_EQ(merge.match(kAutopilotSender, kVehicleSysid, t0 + PhotoMerge::kWindow + 1ms),
              Match::kNew);
}

// A sender's own second command is a second photo (or busy), as before.
TEST(PhotoMerge, TheSameSenderTwiceIsTwoPhotos) {
    PhotoMerge merge;
    const auto t0 = Clock::now();
    merge.begun(kGroundStation190, t0);
    EXPECT_EQ(merge.match(kGroundStation190, kVehicleSysid, t0 + 1ms), Match::kNew);
    merge.begun(kAutopilotSender, t0);
    EXPECT_EQ(merge.match(kAutopilotSender, kVehicleSysid, t0 + 1ms), Match::kNew);
}

// Two ground stations: neither is the vehicle, so nothing forwarded them twice.
TEST(PhotoMerge, TwoGroundStationsAreTwoPhotos) {
    PhotoMerge merge;
    const auto t0 = Clock::now();
    merge.begun(kGroundStation190, t0);
    EXPECT_EQ(merge.match({250, 190}, kVehicleSysid, t0 + 1ms), Match::kNew);
}

// A new photo begun forgets the last one's result.
TEST(PhotoMerge, BegunClearsTheResult) {
    PhotoMerge merge;
    const auto t0 = Clock::now();
    merge.begun(kGroundStation190, t0);
    merge.done(kResultAccepted);
    merge.begun(kGroundStation190, t0 + 1s);
    EXPECT_FALSE(merge.result());
    EXPECT_EQ(merge.match(kAutopilotSender, kVehicleSysid, t0 + 1s + 1ms), Match::kInFlight);
}

}  // namespace
}  // namespace gport::mavlink::bridge
