// Whom gport-mavlink obeys (trust.hpp), each rule with the attack it stops:
// a rogue system id with broadcast targets, a rogue heartbeat sent first,
// a ground station posing as the vehicle's state.
#include <gtest/gtest.h>

#include "gport/mavlink/bridge/trust.hpp"
#include "gport/mavlink/enums.hpp"

namespace gport::mavlink::bridge {
namespace {

Heartbeat autopilot_heartbeat() {
    Heartbeat hb;
    hb.type = 2;       // quadrotor
    hb.autopilot = 3;  // ArduPilot
    return hb;
}

Heartbeat gcs_heartbeat() {
    Heartbeat hb;
    hb.type = mav_type::kGcs;
    hb.autopilot = mav_autopilot::kInvalid;
    return hb;
}

TrustPolicy defaults() {
    TrustPolicy p;
    p.ground_stations.set(255);
    return p;
}

TEST(Trust, DefaultsObeyTheVehicleAndTheGroundStationOnly) {
    const Trust trust(defaults());
    EXPECT_EQ(trust.vehicle(), 1);
    EXPECT_EQ(trust.judge({0, 1, 1}, Concern::kCommand), TrustVerdict::kTrusted);
    EXPECT_EQ(trust.judge({0, 1, 191}, Concern::kCommand), TrustVerdict::kTrusted);  // companion
    EXPECT_EQ(trust.judge({0, 1, 1}, Concern::kVehicleState), TrustVerdict::kTrusted);
    EXPECT_EQ(trust.judge({0, 255, 190}, Concern::kCommand), TrustVerdict::kTrusted);
    EXPECT_EQ(trust.judge({0, 255, 190}, Concern::kOther), TrustVerdict::kTrusted);
}

TEST(Trust, ARogueSystemIdIsAStrangerWhateverItSends) {
    const Trust trust(defaults());
    for (auto concern : {Concern::kCommand, Concern::kVehicleState, Concern::kOther}) {
        EXPECT_EQ(trust.judge({0, 99, 1}, concern), TrustVerdict::kStranger);
        EXPECT_EQ(trust.judge({0, 2, 1}, concern), TrustVerdict::kStranger);
        EXPECT_EQ(trust.judge({0, 0, 0}, concern), TrustVerdict::kStranger);
    }
    EXPECT_EQ(trust.judge({0, 99, 1}, GimbalDeviceSetAttitude::kId), TrustVerdict::kStranger);
    EXPECT_EQ(trust.judge({0, 99, 1}, CommandLong::kId), TrustVerdict::kStranger);
}

TEST(Trust, AGroundStationCannotPoseAsTheVehiclesState) {
    const Trust trust(defaults());
    EXPECT_EQ(trust.judge({0, 255, 190}, Heartbeat::kId), TrustVerdict::kNotVehicle);
    EXPECT_EQ(trust.judge({0, 255, 190}, AutopilotStateForGimbalDevice::kId),
              TrustVerdict::kNotVehicle);
    // Nor its position or attitude (photo geotags, the camera's yaw).
    EXPECT_EQ(trust.judge({0, 255, 190}, GlobalPositionInt::kId), TrustVerdict::kNotVehicle);
    EXPECT_EQ(trust.judge({0, 255, 190}, Attitude::kId), TrustVerdict::kNotVehicle);
    EXPECT_EQ(trust.judge({0, 99, 1}, GlobalPositionInt::kId), TrustVerdict::kStranger);
    EXPECT_EQ(trust.judge({0, 1, 1}, GlobalPositionInt::kId), TrustVerdict::kTrusted);
}

// Our own frames sent back: the vehicle's system id with our component ids
// (the gimbal's 154, the camera's 100). A signed one passes the signature
// check (its stream was never received), so without this rule anyone who
// sees our frames could make themselves the reply peer by returning them.
TEST(Trust, OurOwnFramesSentBackAreNoPeers) {
    TrustPolicy policy = defaults();
    policy.own_components.set(154);
    policy.own_components.set(100);
    const Trust trust(policy);
    for (auto concern : {Concern::kCommand, Concern::kVehicleState, Concern::kOther}) {
        EXPECT_EQ(trust.judge({0, 1, 154}, concern), TrustVerdict::kOwnEcho);
        EXPECT_EQ(trust.judge({0, 1, 100}, concern), TrustVerdict::kOwnEcho);
    }
    EXPECT_EQ(trust.judge({0, 1, 1}, Concern::kCommand), TrustVerdict::kTrusted);
    EXPECT_EQ(trust.judge({0, 255, 154}, Concern::kCommand), TrustVerdict::kTrusted)
        << "a ground station's component ids are its own";
    EXPECT_EQ(to_string(TrustVerdict::kOwnEcho), "our own frame, sent back");
}

TEST(Trust, ARogueHeartbeatFirstIsNotAdoptedWithAFixedSysid) {
    Trust trust(defaults());
    EXPECT_FALSE(trust.on_heartbeat({0, 99, 1}, autopilot_heartbeat()));
    EXPECT_EQ(trust.vehicle(), 1);
    EXPECT_EQ(trust.judge({0, 99, 1}, Concern::kCommand), TrustVerdict::kStranger);
    EXPECT_EQ(trust.judge({0, 1, 1}, Concern::kCommand), TrustVerdict::kTrusted);
}

TEST(Trust, AutoAdoptsTheFirstAutopilotNotAGroundStationOrAGimbal) {
    TrustPolicy policy = defaults();
    policy.vehicle.reset();
    Trust trust(policy);
    EXPECT_TRUE(trust.adopts());
    EXPECT_EQ(trust.judge({0, 7, 1}, Concern::kCommand), TrustVerdict::kNoVehicle);
    EXPECT_EQ(trust.judge({0, 255, 190}, Concern::kCommand), TrustVerdict::kNoVehicle);
    EXPECT_FALSE(trust.on_heartbeat({0, 255, 190}, gcs_heartbeat()));
    Heartbeat gimbal;
    gimbal.type = mav_type::kGimbal;
    gimbal.autopilot = mav_autopilot::kInvalid;
    EXPECT_FALSE(trust.on_heartbeat({0, 9, 154}, gimbal));
    EXPECT_FALSE(trust.on_heartbeat({0, 0, 1}, autopilot_heartbeat()));  // broadcast id
    EXPECT_FALSE(trust.vehicle());
    EXPECT_TRUE(trust.on_heartbeat({0, 7, 1}, autopilot_heartbeat()));
    EXPECT_FALSE(trust.on_heartbeat({0, 8, 1}, autopilot_heartbeat()));  // once only
    EXPECT_EQ(trust.vehicle(), 7);
    EXPECT_EQ(trust.judge({0, 7, 1}, Concern::kCommand), TrustVerdict::kTrusted);
    EXPECT_EQ(trust.judge({0, 8, 1}, Concern::kCommand), TrustVerdict::kStranger);
}

TEST(Trust, AutoIsSpoofableByWhoeverSpeaksFirst) {
    // Documented: with `auto`, a rogue autopilot heartbeat first wins.
    TrustPolicy policy = defaults();
    policy.vehicle.reset();
    Trust trust(policy);
    EXPECT_TRUE(trust.on_heartbeat({0, 99, 1}, autopilot_heartbeat()));
    EXPECT_EQ(trust.judge({0, 1, 1}, Concern::kCommand), TrustVerdict::kStranger);
}

TEST(Trust, NoGroundStationsMeansTheVehicleOnly) {
    TrustPolicy policy;
    policy.vehicle = 3;
    const Trust trust(policy);
    EXPECT_EQ(trust.judge({0, 255, 190}, Concern::kCommand), TrustVerdict::kStranger);
    EXPECT_EQ(trust.judge({0, 3, 1}, Concern::kCommand), TrustVerdict::kTrusted);
    EXPECT_EQ(trust.judge({0, 1, 1}, Concern::kCommand), TrustVerdict::kStranger);
}

TEST(Trust, BroadcastZeroIsNeverAGroundStation) {
    TrustPolicy policy = defaults();
    policy.ground_stations.set(0);
    const Trust trust(policy);
    EXPECT_FALSE(trust.is_ground_station(0));
    EXPECT_EQ(trust.judge({0, 0, 0}, Concern::kCommand), TrustVerdict::kStranger);
}

TEST(Trust, ConcernsByMessage) {
    EXPECT_EQ(concern_of(GimbalDeviceSetAttitude::kId), Concern::kCommand);
    EXPECT_EQ(concern_of(CommandLong::kId), Concern::kCommand);
    EXPECT_EQ(concern_of(Heartbeat::kId), Concern::kVehicleState);
    EXPECT_EQ(concern_of(AutopilotStateForGimbalDevice::kId), Concern::kVehicleState);
    EXPECT_EQ(concern_of(CommandAck::kId), Concern::kOther);
    EXPECT_TRUE(is_autopilot(autopilot_heartbeat()));
    EXPECT_FALSE(is_autopilot(gcs_heartbeat()));
}

}  // namespace
}  // namespace gport::mavlink::bridge
