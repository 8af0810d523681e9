// Notification encoding: the attitude, link and motion payloads of docs/api.md,
// "Notifications".
#include "gport/ipc/event_json.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "gport/protocol/messages.hpp"

namespace gport::ipc {
namespace {

using nlohmann::json;

daemon::AttitudeSample sample_with_rates() {
    daemon::AttitudeSample s;
    s.seq = 1042;
    s.wall = daemon::WallTime(std::chrono::microseconds(1763770000123456));
    s.attitude.imu = {0, 0, -3929};
    s.attitude.hall = {-1921, -16, 466};
    s.attitude.rates = protocol::AttitudeRates{{125, -50, 0}, 12, -230, 0};
    return s;
}

TEST(EventJson, AttitudeNotificationHasTheSpecShape) {
    auto line = attitude_line(sample_with_rates());
    ASSERT_EQ(line->text.back(), '\n');
    EXPECT_EQ(
        line->text,
        R"({"jsonrpc":"2.0","method":"attitude","params":{"seq":1042,"t":1763770000.123456,)"
        R"("imu":{"roll":0,"pitch":0,"yaw":-39.29},"hall":{"roll":-19.21,"pitch":-0.16,"yaw":4.66},)"
        R"("rates":{"hall":{"roll":1.25,"pitch":-0.5,"yaw":0},"imu":{"x":0.12,"y":-2.3,"z":0}}}})"
        "\n");
    auto parsed = json::parse(line->text);
    EXPECT_EQ(parsed["params"]["hall"]["roll"], -19.21);
}

TEST(EventJson, RatesOnlyWhenTheGimbalSentThem) {
    auto s = sample_with_rates();
    s.attitude.rates.reset();
    auto parsed = json::parse(attitude_line(s)->text);
    EXPECT_FALSE(parsed["params"].contains("rates"));
    EXPECT_EQ(parsed["params"]["seq"], 1042);
}

TEST(EventJson, TimeKeepsMicrosecondsWithLeadingZeros) {
    auto s = sample_with_rates();
    s.wall = daemon::WallTime(std::chrono::microseconds(1700000000000042));
    EXPECT_NE(attitude_payload(s).find(R"("t":1700000000.000042)"), std::string::npos);
}

// The `attitude` method builds its result from attitude_json; it must say
// exactly what the notification says, to the last digit.
TEST(EventJson, AttitudeJsonSerialisesLikeThePayload) {
    auto with_rates = sample_with_rates();
    auto without_rates = sample_with_rates();
    without_rates.attitude.rates.reset();
    auto leading_zeros = sample_with_rates();
    leading_zeros.wall = daemon::WallTime(std::chrono::microseconds(1700000000000042));
    auto before_1970 = sample_with_rates();
    before_1970.wall = daemon::WallTime(std::chrono::microseconds(-1500000));
    auto whole = sample_with_rates();  // whole seconds and whole degrees print without a fraction
    whole.wall = daemon::WallTime(std::chrono::seconds(1700000000));
    whole.attitude.imu = {100, -200, 0};
    auto whole_before_1970 = whole;
    whole_before_1970.wall = daemon::WallTime(std::chrono::seconds(-2));
    for (const auto& s :
         {with_rates, without_rates, leading_zeros, before_1970, whole, whole_before_1970}) {
        const json built = attitude_json(s);
        EXPECT_EQ(built, json::parse(attitude_payload(s)));
        EXPECT_EQ(built.dump(), json::parse(attitude_payload(s)).dump());
    }
}

TEST(EventJson, DroppedCountGoesIntoParams) {
    const auto shared = attitude_line(sample_with_rates());
    auto line = with_dropped(*shared, 17);
    auto parsed = json::parse(*line);
    EXPECT_EQ(parsed["params"]["dropped"], 17);
    EXPECT_EQ(parsed["params"]["seq"], 1042);
    EXPECT_EQ(line->back(), '\n');
    // The bytes clients always got: the shared line with the field last in params.
    std::string expected = shared->text;
    expected.insert(expected.size() - 3, R"(,"dropped":17)");
    EXPECT_EQ(*line, expected);
    EXPECT_EQ(shared->text.find("dropped"), std::string::npos) << "the shared line is untouched";
}

// The contract's writer prints every angle and rate the wire can carry as
// fmt's `{}` did (the text gportd always sent), and whole values as integers.
TEST(EventJson, EveryWireValuePrintsAsFmtDid) {
    for (int centi = -32768; centi <= 32767; ++centi) {
        const double value = protocol::from_centi(static_cast<std::int16_t>(centi));
        contract::AttitudePayload payload;
        payload.imu.roll = value;
        const auto text = contract::attitude_payload_text(payload);
        const auto expected = fmt::format(R"("imu":{{"roll":{},)", value);
        ASSERT_NE(text.find(expected), std::string::npos) << centi << ": " << text;
    }
    for (const double odd : {1e-5, -2.5e-7, 1e16, 123456789.125, 0.0001}) {
        contract::AttitudePayload payload;
        payload.hall.yaw = odd;
        const auto text = contract::attitude_payload_text(payload);
        EXPECT_NE(text.find(fmt::format(R"("yaw":{}}})", odd)), std::string::npos) << text;
    }
}

TEST(EventJson, LinkAndMotion) {
    auto link = json::parse(*link_line({daemon::LinkState::kStale, "no attitude for 500 ms"}));
    EXPECT_EQ(link, json({{"jsonrpc", "2.0"},
                          {"method", "link"},
                          {"params", {{"state", "stale"}, {"reason", "no attitude for 500 ms"}}}}));

    daemon::MotionEvent ended;
    ended.change = daemon::MotionChange::kEnded;
    ended.owner = daemon::ClientInfo{3, 100, 1000, 1000, {}};
    ended.speed = {0, 0, 1500};
    ended.duration = daemon::Millis(2000);
    ended.reason = daemon::EndReason::kOwnerGone;
    auto motion = json::parse(*motion_line(ended))["params"];
    EXPECT_EQ(motion["change"], "ended");
    EXPECT_EQ(motion["mode"], "speed");
    EXPECT_EQ(motion["reason"], "owner_gone");
    EXPECT_EQ(motion["owner"]["pid"], 100);
    EXPECT_EQ(motion["speed"]["yaw"], 15.0);
    EXPECT_EQ(motion["duration_ms"], 2000);
    EXPECT_FALSE(motion.contains("braked")) << "only braking events carry braked";

    daemon::MotionEvent braked;
    braked.change = daemon::MotionChange::kUpdated;
    braked.speed = {0, 0, 1500};
    braked.reason = daemon::EndReason::kLimit;
    braked.braked = {"pitch"};
    auto b = json::parse(*motion_line(braked))["params"];
    EXPECT_EQ(b["change"], "updated");
    EXPECT_EQ(b["reason"], "limit");
    EXPECT_EQ(b["braked"], json::array({"pitch"}));
    braked.change = daemon::MotionChange::kEnded;
    braked.reason = daemon::EndReason::kNoAttitude;
    EXPECT_EQ(json::parse(*motion_line(braked))["params"]["reason"], "no_attitude");

    daemon::MotionEvent angle;
    angle.mode = daemon::MotionMode::kAngle;
    angle.angle = {0, -9000, 0};
    auto a = json::parse(*motion_line(angle))["params"];
    EXPECT_EQ(a["angle"]["pitch"], -90.0);
    EXPECT_FALSE(a.contains("reason"));
    EXPECT_TRUE(a["owner"].is_null());
    EXPECT_EQ(a["target"], a["angle"]) << "tracked motions name their target";

    daemon::MotionEvent centre;
    centre.change = daemon::MotionChange::kEnded;
    centre.mode = daemon::MotionMode::kCenter;
    centre.reason = daemon::EndReason::kReached;
    auto c = json::parse(*motion_line(centre))["params"];
    EXPECT_EQ(c["target"], json({{"roll", 0.0}, {"pitch", 0.0}, {"yaw", 0.0}}));
    EXPECT_EQ(c["reason"], "reached");
}

}  // namespace
}  // namespace gport::ipc
