// The client's JSON codec on its own: the shapes of docs/api.md and of the
// API additions (tracked motions with `ended`, braking events), without a
// daemon. The codec is internal to the library, so its sources are compiled in.
#include "codec.hpp"

#include <gtest/gtest.h>

#include <limits>

#include "attitude_feed.hpp"
#include "connect_error.hpp"

namespace gport::client::codec {
namespace {

TEST(ClientCodec, OptionsAreSentOnlyWhenSet) {
    EXPECT_EQ(angle_params({.yaw = 5}, {}), json::parse(R"({"roll":0,"pitch":0,"yaw":5})"));
    EXPECT_EQ(angle_params({}, {.clamp = true, .wait = true})["wait"], true);
    EXPECT_EQ(center_params({}), json::object());
    EXPECT_EQ(center_params({.wait = true}), json::parse(R"({"wait":true})"));
    const auto speed = speed_params(
        {.pitch = 2}, {std::chrono::milliseconds(900), std::chrono::milliseconds(300), true});
    EXPECT_EQ(speed["duration_ms"], 900);
    EXPECT_EQ(speed["lease_ms"], 300);
    EXPECT_EQ(speed["clamp"], true);
    EXPECT_FALSE(speed_params({}, {}).contains("lease_ms"));
    EXPECT_EQ(record_params(std::nullopt, true), json::object()) << "force needs on";
    EXPECT_EQ(record_params(false, true), json::parse(R"({"on":false,"force":true})"));
    EXPECT_EQ(settings_params({.inverted = true}), json::parse(R"({"inverted":true})"));
    EXPECT_EQ(unsubscribe_params({}), json::object()) << "no topics: all";
    EXPECT_EQ(subscribe_params({"link"}, std::nullopt), json::parse(R"({"topics":["link"]})"));
}

TEST(ClientCodec, CaptureMetaMustBeAJsonObject) {
    json params = record_params(true, false);
    EXPECT_FALSE(add_meta(params, {}));
    EXPECT_FALSE(params.contains("meta")) << "no meta: none sent";
    EXPECT_FALSE(add_meta(params, {.meta = R"({"lat":47.1,"lon":8.5})"}));
    EXPECT_EQ(params, json::parse(R"({"on":true,"meta":{"lat":47.1,"lon":8.5}})"));
    for (const char* bad : {"[1,2]", "42", "{\"lat\":", "not json"}) {
        json p = json::object();
        const auto error = add_meta(p, {.meta = bad});
        ASSERT_TRUE(error) << bad;
        EXPECT_TRUE(error->is(ErrorCode::kInvalidParams));
        EXPECT_NE(error->message().find("JSON object"), std::string::npos);
        EXPECT_FALSE(p.contains("meta"));
    }
}

TEST(ClientCodec, PhotoAndRecordCarryTheCaptureWhenGportdLogsIt) {
    EXPECT_FALSE(photo_result(json::object()).capture) << "a gportd without the log";
    const auto photo = photo_result(
        json::parse(R"({"capture":{"index":41,"utc_us":1764000000123456,"kind":"photo"}})"));
    ASSERT_TRUE(photo.capture);
    EXPECT_EQ(photo.capture->index, 41U);
    EXPECT_EQ(photo.capture->utc_us, 1764000000123456U);
    EXPECT_EQ(photo.capture->kind, "photo");
    const auto record = record_result(json::parse(
        R"({"sent":true,"recording":"on","capture":{"index":42,"kind":"record_start"}})"));
    ASSERT_TRUE(record.capture);
    EXPECT_EQ(record.capture->index, 42U);
    EXPECT_FALSE(record.capture->utc_us);
    EXPECT_FALSE(record_result(json::parse(R"({"sent":false,"recording":"on"})")).capture);
    EXPECT_THROW(photo_result(json::parse(R"({"capture":{"index":"x"}})")), Error);
}

TEST(ClientCodec, APhotoReportCarriesTheAttitudeGportdLogged) {
    const auto report = photo_report(json::parse(
        R"({"capture":{"index":7,"kind":"photo","attitude":{"imu":{"roll":0.5,"pitch":-30.25,)"
        R"("yaw":12},"hall":{"roll":0.1,"pitch":-29.9,"yaw":20.5},"age_ms":14}}})"));
    ASSERT_TRUE(report.capture);
    EXPECT_EQ(report.capture->index, 7U);
    ASSERT_TRUE(report.attitude);
    EXPECT_EQ(report.attitude->imu.pitch, -30.25);
    EXPECT_EQ(report.attitude->hall.yaw, 20.5);
    EXPECT_EQ(report.attitude->age_ms, 14);
    EXPECT_FALSE(
        photo_report(json::parse(R"({"capture":{"index":8,"kind":"photo","attitude":null}})"))
            .attitude);
    EXPECT_FALSE(photo_report(json::parse(R"({"capture":{"index":9,"kind":"photo"}})")).attitude);
    EXPECT_FALSE(photo_report(json::object()).capture);
}

TEST(ClientCodec, ErrorsBecomeErrorWithTheirCode) {
    try {
        result_of(json::parse(R"({"id":1,"error":{"code":-32003,"message":"held by pid 7"}})"));
        FAIL() << "no throw";
    } catch (const Error& e) {
        EXPECT_TRUE(e.is(ErrorCode::kBusy));
        EXPECT_EQ(e.message(), "held by pid 7");
    }
    EXPECT_EQ(result_of(json::parse(R"({"id":1,"result":{"sent":true}})"))["sent"], true);
    for (const char* bad : {R"([1])", R"({"id":1})", R"({"id":1,"error":{"message":"x"}})"}) {
        try {
            result_of(json::parse(bad));
            FAIL() << bad;
        } catch (const Error& e) {
            EXPECT_TRUE(e.is(ErrorCode::kBadReply)) << bad;
        }
    }
}

TEST(ClientCodec, AngleWaitResultCarriesTheEnd) {
    const auto r = angle_result(json::parse(R"({"sent":true,"angle":{"roll":0,"pitch":-90,"yaw":45},
        "clamped":["pitch"],"ended":{"reason":"reached","elapsed_ms":812,
        "attitude":{"seq":9,"t":1763770000.5,"imu":{"roll":0,"pitch":-89.9,"yaw":45},
                    "hall":{"roll":0,"pitch":-90,"yaw":44.8},"age_ms":3}}})"));
    EXPECT_EQ(r.angle.pitch, -90);
    EXPECT_EQ(r.clamped, std::vector<std::string>{"pitch"});
    ASSERT_TRUE(r.ended.has_value());
    EXPECT_EQ(r.ended->reason, "reached");
    EXPECT_EQ(r.ended->elapsed_ms, 812);
    ASSERT_TRUE(r.ended->attitude.has_value());
    EXPECT_EQ(r.ended->attitude->seq, 9U);
    EXPECT_EQ(r.ended->attitude->age_ms, 3);
    const auto none = center_result(json::parse(
        R"({"sent":true,"ended":{"reason":"link_down","elapsed_ms":5,"attitude":null}})"));
    ASSERT_TRUE(none.ended.has_value());
    EXPECT_FALSE(none.ended->attitude.has_value()) << "null when there is no sample";
    EXPECT_EQ(none.ended->detail, "") << "no detail unless stalled";
    const auto stalled = angle_result(json::parse(
        R"({"sent":true,"ended":{"reason":"stalled","elapsed_ms":2400,"attitude":null,
            "detail":"stalled at pitch -90.00 (target -100.00, 10.00° short): no progress"}})"));
    ASSERT_TRUE(stalled.ended.has_value());
    EXPECT_EQ(stalled.ended->reason, "stalled");
    EXPECT_EQ(stalled.ended->detail,
              "stalled at pitch -90.00 (target -100.00, 10.00° short): no progress");
}

TEST(ClientCodec, AttitudeWithRatesAndDrops) {
    const auto n = notification(json::parse(R"({"jsonrpc":"2.0","method":"attitude","params":
        {"seq":1042,"t":1763770000.123456,"imu":{"roll":0,"pitch":0,"yaw":-39.29},
         "hall":{"roll":-19.21,"pitch":-0.16,"yaw":4.66},"dropped":3,
         "rates":{"hall":{"roll":1.25,"pitch":-0.5,"yaw":0},"imu":{"x":0.12,"y":-2.3,"z":0}}}})"));
    ASSERT_TRUE(n.has_value());
    const auto& s = std::get<AttitudeSample>(*n);
    EXPECT_EQ(s.seq, 1042U);
    EXPECT_DOUBLE_EQ(s.time, 1763770000.123456);
    EXPECT_DOUBLE_EQ(s.imu.yaw, -39.29);
    EXPECT_EQ(s.dropped, 3U);
    ASSERT_TRUE(s.rates.has_value());
    EXPECT_DOUBLE_EQ(s.rates->hall.roll, 1.25);
    EXPECT_DOUBLE_EQ(s.rates->imu.y, -2.3);
}

// gportctl watch --shared-memory prints ring samples with this: the values
// gportd's notification of the same sample has (whole numbers as integers,
// as gportd prints them; dropped only when some were missed), and the
// decoder reads them back unchanged.
TEST(ClientCodec, AttitudeNotificationIsWhatGportdSends) {
    const auto sent = json::parse(R"({"jsonrpc":"2.0","method":"attitude","params":
        {"seq":1042,"t":1763770000.123456,"imu":{"roll":0,"pitch":0,"yaw":-39.29},
         "hall":{"roll":-19.21,"pitch":-0.16,"yaw":45},"dropped":3,
         "rates":{"hall":{"roll":1.25,"pitch":-0.5,"yaw":0},"imu":{"x":0.12,"y":-2.3,"z":0}}}})");
    const auto sample = std::get<AttitudeSample>(*notification(sent));
    const auto made = attitude_notification(sample);
    EXPECT_EQ(made, sent);
    EXPECT_EQ(made["params"]["hall"]["yaw"].dump(), "45") << "an integer, as gportd prints it";
    EXPECT_EQ(std::get<AttitudeSample>(*notification(made)).hall.roll, -19.21);

    AttitudeSample plain = sample;
    plain.dropped = 0;
    plain.rates.reset();
    const auto without = attitude_notification(plain)["params"];
    EXPECT_FALSE(without.contains("dropped")) << "gportd sends it only after a drop";
    EXPECT_FALSE(without.contains("rates"));
}

// A hostile server's numbers that are not finite (1e999 reads as infinity)
// print as null, as nlohmann writes them, and never throw.
TEST(ClientCodec, AttitudeNotificationOfNumbersThatAreNotFinite) {
    AttitudeSample sample;
    sample.seq = 7;
    sample.time = std::numeric_limits<double>::infinity();
    sample.hall.roll = std::numeric_limits<double>::quiet_NaN();
    sample.imu.yaw = -std::numeric_limits<double>::infinity();
    const auto made = attitude_notification(sample);
    EXPECT_TRUE(made["params"]["hall"]["roll"].is_null());
    EXPECT_TRUE(made["params"]["imu"]["yaw"].is_null());
    EXPECT_EQ(made["params"]["seq"], 7);
    EXPECT_EQ(made.dump().find("inf"), std::string::npos);
}

TEST(ClientCodec, MotionEventsOfEveryKind) {
    const auto braked = notification(json::parse(R"({"method":"motion","params":
        {"change":"updated","mode":"speed","owner":{"id":4,"pid":812,"uid":1000,"gid":1000},
         "speed":{"roll":0,"pitch":0,"yaw":20},"reason":"limit","braked":["pitch"]}})"));
    const auto& b = std::get<MotionEvent>(*braked);
    EXPECT_EQ(b.change, "updated");
    EXPECT_EQ(b.reason, "limit");
    EXPECT_EQ(b.braked, std::vector<std::string>{"pitch"});
    EXPECT_EQ(b.owner->pid, 812);
    const auto tracked = notification(json::parse(R"({"method":"motion","params":
        {"change":"ended","mode":"angle","owner":null,"target":{"roll":0,"pitch":-10,"yaw":30},
         "reason":"reached"}})"));
    const auto& t = std::get<MotionEvent>(*tracked);
    EXPECT_FALSE(t.owner.has_value());
    ASSERT_TRUE(t.target.has_value());
    EXPECT_EQ(t.target->yaw, 30);
    EXPECT_FALSE(t.speed.has_value());
    const auto link = notification(json::parse(
        R"({"method":"link","params":{"state":"stale","reason":"no attitude for 500 ms"}})"));
    EXPECT_EQ(std::get<LinkEvent>(*link).state, "stale");
    EXPECT_FALSE(notification(json::parse(R"({"method":"weather","params":{}})")).has_value())
        << "an unknown topic is not an error";
    EXPECT_THROW(notification(json::parse(R"({"method":"attitude","params":{"seq":"x"}})")), Error);
}

TEST(ClientCodec, StatusWithATrackedMotionAndUnknownMembers) {
    const auto s = status(json::parse(R"({"api_version":1,"daemon_version":"0.2.0",
        "link":{"state":"up","reason":"attitude arriving"},"device":"/dev/gimbal",
        "device_open":true,"uptime_ms":5,"attitude_age_ms":null,"counters":{"frames_in":3,
        "something_new":1},"clients":2,"dropped_notifications":0,
        "motion":{"mode":"angle","owner":{"id":1,"pid":2,"uid":3,"gid":4},
                  "target":{"roll":0,"pitch":-10,"yaw":30},"elapsed_ms":120},
        "controller":null,"recording":"off","client":{"id":7,"pid":990,"uid":0,"gid":0,"dropped":4},
        "a_future_member":true})"));
    EXPECT_EQ(s.counters.frames_in, 3U);
    EXPECT_FALSE(s.attitude_age_ms.has_value());
    ASSERT_TRUE(s.motion.has_value());
    EXPECT_EQ(s.motion->mode, "angle");
    EXPECT_EQ(s.motion->target->pitch, -10);
    EXPECT_EQ(s.motion->elapsed_ms, 120);
    EXPECT_FALSE(s.motion->time_left_ms.has_value());
    EXPECT_EQ(s.self.id, 7);
    EXPECT_EQ(s.self_dropped, 4U);
    EXPECT_EQ(s.recording, "off");
}

TEST(ConnectFailure, PermissionDeniedSaysToJoinTheGportGroup) {
    const auto denied = detail::connect_failure("/run/gportd.sock", EACCES, "Permission denied");
    EXPECT_NE(denied.find("cannot connect to /run/gportd.sock: Permission denied"),
              std::string::npos);
    EXPECT_NE(denied.find("members of the gport group"), std::string::npos);
    EXPECT_NE(denied.find("usermod -aG gport"), std::string::npos);
    EXPECT_EQ(denied.find("is gportd running"), std::string::npos);
    const auto absent = detail::connect_failure("/run/gportd.sock", ENOENT, "No such file");
    EXPECT_NE(absent.find("(is gportd running?)"), std::string::npos);
}

}  // namespace
}  // namespace gport::client::codec
