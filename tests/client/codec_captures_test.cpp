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
