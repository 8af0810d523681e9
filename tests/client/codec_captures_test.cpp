// The capture log's codec (issue 32): captures pages, entries and the
// capture topic, unhappy shapes first.
#include <gtest/gtest.h>

#include "codec.hpp"

namespace gport::client::codec {
namespace {

TEST(CapturesCodec, ShapesGportdNeverSendsAreBadReplies) {
    for (const auto* text : {R"({})", R"({"captures":{}})", R"({"captures":[1]})",
                             R"({"captures":[{"index":"x"}]})", R"([])"}) {
        try {
            captures_page(json::parse(text), 0);
            ADD_FAILURE() << text;
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), static_cast<int>(ErrorCode::kBadReply)) << text;
        }
    }
    EXPECT_THROW(capture_notification(json::parse(R"({"method":"capture","params":[]})")), Error);
}

TEST(CapturesCodec, APageThatDoesNotAdvanceEndsThePaging) {
    const auto stuck = captures_page(
        json::parse(R"({"captures":[{"index":3,"kind":"photo"}],"more":true,"next":3})"), 3);
    EXPECT_FALSE(stuck.more);
    // A gportd before `more`: more while pages are not empty.
    const auto old =
        captures_page(json::parse(R"({"captures":[{"index":3,"kind":"photo"}],"next":4})"), 0);
    EXPECT_TRUE(old.more);
    EXPECT_EQ(old.next, 4U);
    const auto empty = captures_page(json::parse(R"({"captures":[],"next":9})"), 9);
    EXPECT_FALSE(empty.more);
    EXPECT_EQ(empty.next, 9U);
}

TEST(CapturesCodec, EntriesCarryAttitudeMetaAndClient) {
    const auto page = captures_page(json::parse(R"({"captures":[
        {"index":12,"utc_us":1795563183085470,"kind":"photo",
         "attitude":{"imu":{"roll":0.5,"pitch":-30,"yaw":1},"hall":{"roll":0,"pitch":-29.5,"yaw":2},
                     "age_ms":4},
         "client":{"pid":40,"uid":1000,"name":"flight.py"},
         "meta":{"lat":47.397742,"lon":8.545594,"alt_m":488.5}},
        {"index":13,"kind":"record_start","attitude":null}],"more":false,"next":14})"),
                                    0);
    ASSERT_EQ(page.captures.size(), 2U);
    EXPECT_FALSE(page.more);
    EXPECT_EQ(page.next, 14U);
    const auto& first = page.captures[0];
    EXPECT_EQ(first.capture.index, 12U);
    EXPECT_EQ(first.capture.utc_us, 1795563183085470U);
    ASSERT_TRUE(first.attitude);
    EXPECT_EQ(first.attitude->hall.pitch, -29.5);
    EXPECT_EQ(json::parse(first.meta)["lat"], 47.397742);
    ASSERT_TRUE(first.client);
    EXPECT_EQ(first.client->pid, 40);
    EXPECT_EQ(first.client_name, "flight.py");
    const auto& second = page.captures[1];
    EXPECT_EQ(second.capture.kind, "record_start");
    EXPECT_FALSE(second.attitude);
    EXPECT_EQ(second.meta, "");
    EXPECT_FALSE(second.client);
}

TEST(CapturesCodec, TheCaptureTopicAndOnlyIt) {
    EXPECT_FALSE(capture_notification(json::parse(R"({"method":"link","params":{}})")));
    const auto entry = capture_notification(
        json::parse(R"({"method":"capture","params":{"index":5,"kind":"photo"}})"));
    ASSERT_TRUE(entry);
    EXPECT_EQ(entry->capture.index, 5U);
    EXPECT_EQ(captures_params(5, std::nullopt), json({{"since", 5}}));
    EXPECT_EQ(captures_params(0, 64), json({{"since", 0}, {"limit", 64}}));
}

}  // namespace
}  // namespace gport::client::codec

namespace gport::client::codec {
namespace {

// A capture's moment and vehicle (1.10.0): a server that lies about them
// is a bad reply naming the vehicle, never a crash nor a made-up position.
TEST(CaptureStampCodec, AVehicleGportdNeverSendsIsABadReply) {
    for (const auto* text :
         {R"({"vehicle":1})", R"({"vehicle":{}})", R"({"vehicle":{"tagged":"yes"}})",
          R"({"vehicle":{"tagged":true}})",
          R"({"vehicle":{"tagged":true,"lat":"47","lon":8,"alt_msl_m":1}})", R"({"vehicle":[]})"}) {
        try {
            capture_stamp(json::parse(text));
            ADD_FAILURE() << text;
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), static_cast<int>(ErrorCode::kBadReply)) << text;
            EXPECT_NE(e.message().find("vehicle"), std::string::npos) << e.message();
        }
    }
    EXPECT_THROW(capture_stamp(json::parse("[]")), Error);
}

TEST(CaptureStampCodec, TaggedUntaggedAndAnOlderGportd) {
    const auto tagged = capture_stamp(json::parse(R"({"line_mono_us":5000,"shutter_mono_us":5100,
        "vehicle":{"tagged":true,"utc_us":1795910400000000,"lat":47.1,"lon":8.2,"alt_msl_m":500,
        "alt_rel_m":null,"velocity_ned":[15,0,"x"],"heading_deg":90,"h_acc_m":1.5,"v_acc_m":null,
        "fix":3,"satellites":300,"age_ms":120}})"));
    EXPECT_EQ(tagged.line_mono_us, 5000);
    EXPECT_EQ(tagged.shutter_mono_us, 5100);
    ASSERT_TRUE(tagged.vehicle);
    EXPECT_TRUE(tagged.vehicle->tagged);
    EXPECT_DOUBLE_EQ(tagged.vehicle->lat, 47.1);
    EXPECT_EQ(tagged.vehicle->utc_us, 1795910400000000);
    EXPECT_FALSE(tagged.vehicle->alt_rel_m);
    EXPECT_EQ(tagged.vehicle->velocity_ned[0], 0.0) << "a mistyped velocity is not taken";
    EXPECT_EQ(tagged.vehicle->h_acc_m, 1.5);
    EXPECT_EQ(tagged.vehicle->fix, 3);
    EXPECT_FALSE(tagged.vehicle->satellites) << "out of range";
    EXPECT_EQ(tagged.vehicle->age_ms, 120);

    const auto untagged = capture_stamp(
        json::parse(R"({"vehicle":{"tagged":false,"utc_us":null,"why":"no 3D GPS fix"}})"));
    ASSERT_TRUE(untagged.vehicle);
    EXPECT_FALSE(untagged.vehicle->tagged);
    EXPECT_EQ(untagged.vehicle->why, "no 3D GPS fix");

    const auto older = capture_stamp(json::parse(R"({"index":3,"kind":"photo"})"));
    EXPECT_FALSE(older.line_mono_us);
    EXPECT_FALSE(older.vehicle);
    EXPECT_FALSE(capture_stamp(json::parse(R"({"vehicle":null})")).vehicle);
}

TEST(VehicleCodec, ReportsSendOnlyWhatIsKnown) {
    VehicleReport report;
    report.position = VehiclePosition{};
    report.position->boot_ms = 1000;
    report.position->lat = 47.5;
    report.position->h_acc_m = 0.8;
    EXPECT_EQ(vehicle_params(report),
              json::parse(R"({"position":{"boot_ms":1000,"lat":47.5,"lon":0.0,"alt_msl_m":0.0,
                              "velocity_ned":[0.0,0.0,0.0],"h_acc_m":0.8}})"));
    report.position.reset();
    report.time = VehicleTime{2000, 1795910400000000};
    EXPECT_EQ(vehicle_params(report),
              json::parse(R"({"time":{"boot_ms":2000,"utc_us":1795910400000000}})"));
}

}  // namespace
}  // namespace gport::client::codec
