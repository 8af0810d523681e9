// The capture log through the dispatcher (photo and record with meta, the
// captures method, status); CaptureLog itself is tests/capture's.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>
#include <variant>
#include <vector>

#include "fake_api.hpp"
#include "fake_capture_sink.hpp"
#include "gport/capture/capture_log.hpp"
#include "gport/ipc/json_rpc.hpp"

namespace gport::ipc {
namespace {

using gport::testing::FakeSink;
using nlohmann::json;
using ::testing::HasSubstr;

class CapturesTest : public ::testing::Test {
  protected:
    json call(std::string_view method, json params = nullptr) {
        json request = {{"jsonrpc", "2.0"}, {"id", 1}, {"method", method}};
        if (!params.is_null()) {
            request["params"] = std::move(params);
        }
        json reply;
        dispatcher_.handle_line(request.dump(), client_,
                                [&](std::string line) { reply = json::parse(line); });
        return reply;
    }
    // A meta object whose compact JSON is exactly `bytes` long.
    static json meta_of(std::size_t bytes) {
        const std::size_t overhead = json({{"s", ""}}).dump().size();
        return json{{"s", std::string(bytes - overhead, 'x')}};
    }

    testing::FakeApi api_;
    ClientState client_{{7, 4242, 1000, 1000, {}}, {}, 0, {}};
    Dispatcher dispatcher_{api_, [] { return ServerStats{}; }};
};

// issue 43: the vehicle the core stamped each capture with, in the reply's
// summary, the log's line and the captures list, with the moment on the line.
TEST_F(CapturesTest, CapturesCarryTheVehicleAndTheirMomentOnTheLine) {
    EXPECT_TRUE(call("photo")["result"]["capture"]["vehicle"].is_null()) << "nothing published";
    daemon::VehicleStamp stamp;
    stamp.tagged = true;
    stamp.lat_deg = 47.123456789;
    stamp.lon_deg = 8.5;
    stamp.alt_msl_m = 500.25;
    stamp.h_acc_m = 1.75;
    stamp.age = std::chrono::milliseconds(120);
    stamp.utc_us = 1795910400123456;
    api_.vehicle_stamp = stamp;
    const auto photo = call("photo")["result"]["capture"];
    EXPECT_EQ(photo["vehicle"]["tagged"], true);
    EXPECT_EQ(photo["vehicle"]["lat"], 47.12345679);
    EXPECT_EQ(photo["vehicle"]["h_acc_m"], 1.75);
    EXPECT_EQ(photo["vehicle"]["age_ms"], 120);
    EXPECT_EQ(photo["vehicle"]["utc_us"], 1795910400123456);
    EXPECT_TRUE(photo["vehicle"]["heading_deg"].is_null());

    stamp = daemon::VehicleStamp{};
    stamp.why = "no 3D GPS fix (GPS_FIX_TYPE 1)";
    api_.vehicle_stamp = stamp;
    const auto untagged = call("photo")["result"]["capture"]["vehicle"];
    EXPECT_EQ(
        untagged,
        json::parse(R"j({"tagged":false,"utc_us":null,"why":"no 3D GPS fix (GPS_FIX_TYPE 1)"})j"));

    const auto list = call("captures")["result"]["captures"];
    ASSERT_EQ(list.size(), 3u);
    EXPECT_TRUE(list[1]["line_mono_us"].is_number_integer());
    EXPECT_GE(list[1]["shutter_mono_us"].get<std::int64_t>(),
              list[1]["line_mono_us"].get<std::int64_t>());
    EXPECT_EQ(list[1]["vehicle"]["lat"], 47.12345679);
    EXPECT_EQ(list[2]["vehicle"]["tagged"], false);
}

// publish_vehicle's params: every shape refused names the member and what it
// must be; nothing reaches the core.
TEST_F(CapturesTest, PublishVehicleParamsNameWhatIsWrong) {
    const auto refused = [&](json params) {
        const auto reply = call("publish_vehicle", std::move(params));
        EXPECT_EQ(reply["error"]["code"], -32602) << reply.dump();
        return reply["error"]["message"].get<std::string>();
    };
    const json position = {{"boot_ms", 1000},
                           {"lat", 47.0},
                           {"lon", 8.0},
                           {"alt_msl_m", 500.0},
                           {"velocity_ned", {1.0, 0.0, 0.0}}};
    EXPECT_THAT(refused({{"position", 1}}), HasSubstr("position must be an object"));
    EXPECT_THAT(refused({{"pos", position}}), HasSubstr("unknown parameter"));
    auto p = position;
    p.erase("lat");
    EXPECT_THAT(refused({{"position", p}}), HasSubstr("position.lat is required"));
    p = position;
    p["lat"] = "47";
    EXPECT_THAT(refused({{"position", p}}), HasSubstr("position.lat must be a number"));
    p = position;
    p["velocity_ned"] = {1.0, 2.0};
    EXPECT_THAT(refused({{"position", p}}),
                HasSubstr("position.velocity_ned is required: [north, east, down]"));
    p = position;
    p["speed"] = 3;
    EXPECT_THAT(refused({{"position", p}}), HasSubstr("position: unknown parameter \"speed\""));
    p = position;
    p["boot_ms"] = -1;
    EXPECT_THAT(refused({{"position", p}}),
                HasSubstr("position.boot_ms must be an integer from 0 to 4294967295"));
    EXPECT_THAT(refused({{"time", {{"boot_ms", 1}}}}), HasSubstr("time.utc_us is required"));
    EXPECT_TRUE(api_.vehicle_reports.empty());

    const auto taken =
        call("publish_vehicle",
             {{"position", position}, {"time", {{"boot_ms", 1000}, {"utc_us", 1795910400000000}}}});
    EXPECT_EQ(taken["result"], json({{"taken", true}}));
    ASSERT_EQ(api_.vehicle_reports.size(), 1u);
    EXPECT_EQ(api_.vehicle_reports[0].position->velocity_ned[0], 1.0);
    EXPECT_EQ(api_.vehicle_reports[0].time->utc_us, 1795910400000000);
}

TEST_F(CapturesTest, MetaOverTheLimitIsRefusedNamingItAndNothingIsSent) {
    auto refused = call("photo", {{"meta", meta_of(1025)}});
    EXPECT_EQ(refused["error"]["code"], -32602);
    EXPECT_THAT(refused["error"]["message"].get<std::string>(), HasSubstr("1025 bytes"));
    EXPECT_THAT(refused["error"]["message"].get<std::string>(), HasSubstr("at most 1024"));
    refused = call("record", {{"meta", meta_of(4096)}});
    EXPECT_EQ(refused["error"]["code"], -32602);
    EXPECT_TRUE(api_.calls.empty()) << "a refused meta must not reach the gimbal";
    EXPECT_TRUE(call("captures")["result"]["captures"].empty());

    auto taken = call("photo", {{"meta", meta_of(1024)}});
    EXPECT_EQ(taken["result"]["sent"], true);
    EXPECT_EQ(call("captures")["result"]["captures"][0]["meta"], meta_of(1024));
}

TEST_F(CapturesTest, MetaThatIsNotAnObjectIsRefused) {
    for (const auto& meta : {json::array({1}), json("lat"), json(3), json(nullptr)}) {
        auto refused = call("photo", {{"meta", meta}});
        EXPECT_EQ(refused["error"]["code"], -32602) << meta.dump();
        EXPECT_THAT(refused["error"]["message"].get<std::string>(), HasSubstr("JSON object"));
    }
    EXPECT_TRUE(api_.calls.empty());
}

TEST_F(CapturesTest, ARefusedCommandMakesNoCapture) {
    api_.error = daemon::CommandError{daemon::ErrorCode::kLinkDown, "no device"};
    EXPECT_EQ(call("photo")["error"]["code"], -32000);
    EXPECT_EQ(call("record")["error"]["code"], -32000);
    api_.error.reset();
    api_.record_result = {false, daemon::RecordingState::kOn};  // already on: nothing sent
    auto unsent = call("record", {{"on", true}});
    EXPECT_FALSE(unsent["result"].contains("capture"));
    EXPECT_TRUE(call("captures")["result"]["captures"].empty());
}

TEST_F(CapturesTest, RepliesCarryTheCaptureAndKindsFollowTheRecordingState) {
    daemon::AttitudeSample sample;
    sample.received = std::chrono::steady_clock::now();
    sample.attitude.imu = {100, -2050, 3000};
    sample.attitude.hall = {0, -2000, 2990};
    api_.attitude = sample;

    auto photo = call("photo", {{"meta", {{"lat", 47.1}, {"lon", 8.5}, {"alt_m", 512.0}}}});
    EXPECT_EQ(photo["result"]["sent"], true);
    EXPECT_EQ(photo["result"]["capture"]["index"], 1);
    EXPECT_EQ(photo["result"]["capture"]["kind"], "photo");
    EXPECT_GT(photo["result"]["capture"]["utc_us"].get<std::int64_t>(), 1600000000000000);

    api_.record_result = {true, daemon::RecordingState::kUnknown};
    EXPECT_EQ(call("record")["result"]["capture"]["kind"], "record_toggle");
    api_.record_result = {true, daemon::RecordingState::kOn};
    auto start = call("record", {{"on", true}, {"force", true}});
    EXPECT_EQ(start["result"]["capture"]["kind"], "record_start");
    EXPECT_EQ(start["result"]["recording"], "on");
    api_.record_result = {true, daemon::RecordingState::kOff};
    EXPECT_EQ(call("record", {{"on", false}})["result"]["capture"]["kind"], "record_stop");

    const auto list = call("captures")["result"];
    ASSERT_EQ(list["captures"].size(), 4u);
    EXPECT_EQ(list["next"], 5);
    const auto& first = list["captures"][0];
    EXPECT_EQ(first["attitude"]["imu"], json({{"roll", 1.0}, {"pitch", -20.5}, {"yaw", 30.0}}));
    EXPECT_EQ(first["attitude"]["hall"]["yaw"], 29.9);
    EXPECT_GE(first["attitude"]["age_ms"].get<std::int64_t>(), 0);
    EXPECT_EQ(first["client"]["pid"], 4242);
    EXPECT_EQ(first["client"]["uid"], 1000);
    EXPECT_EQ(first["meta"]["lat"], 47.1);
    EXPECT_TRUE(first["mono_us"].is_number_integer());
    EXPECT_FALSE(list["captures"][1].contains("meta"));
}

TEST_F(CapturesTest, WithoutAttitudeTheCaptureSaysNull) {
    call("photo");
    EXPECT_TRUE(call("captures")["result"]["captures"][0]["attitude"].is_null());
}

TEST_F(CapturesTest, SinceAndLimitPageThroughAndAreChecked) {
    for (int i = 0; i < 5; ++i) {
        call("photo");
    }
    auto page = call("captures", {{"since", 2}, {"limit", 2}})["result"];
    ASSERT_EQ(page["captures"].size(), 2u);
    EXPECT_EQ(page["captures"][0]["index"], 2);
    EXPECT_EQ(page["next"], 4);
    page = call("captures", {{"since", page["next"]}, {"limit", 1000}})["result"];
    EXPECT_EQ(page["captures"].size(), 2u);
    EXPECT_EQ(page["next"], 6);
    page = call("captures", {{"since", 6}})["result"];
    EXPECT_TRUE(page["captures"].empty());
    EXPECT_EQ(page["next"], 6) << "the index the next capture will get";

    for (const auto& bad :
         {json{{"limit", 0}}, json{{"limit", 1001}}, json{{"since", -1}}, json{{"since", "1"}},
          json{{"from", 1}},
          // 2^63, which equals double(INT64_MAX): out of range, not UB
          json{{"since", 9223372036854775808.0}}, json{{"since", 1e300}}, json{{"since", 2.5}}}) {
        EXPECT_EQ(call("captures", bad)["error"]["code"], -32602) << bad.dump();
    }
    EXPECT_THAT(call("captures", {{"limit", 1001}})["error"]["message"].get<std::string>(),
                HasSubstr("1000"));
}

// A batch of `captures` pages over a log of 1 KiB metas: the batch's line
// stays within its budget (so it fits the client's 256 KiB output queue
// and the client is not disconnected); the members past it get -32600
// naming the limit.
TEST_F(CapturesTest, ABatchOfPagesFitsTheClientsQueue) {
    for (int i = 0; i < 300; ++i) {
        ASSERT_EQ(call("photo", {{"meta", meta_of(1000)}})["result"]["sent"], true);
    }
    json batch = json::array();
    for (int i = 1; i <= 8; ++i) {
        batch.push_back(
            {{"jsonrpc", "2.0"}, {"id", i}, {"method", "captures"}, {"params", {{"limit", 1000}}}});
    }
    std::string line;
    dispatcher_.handle_line(batch.dump(), client_, [&](std::string l) { line = std::move(l); });
    EXPECT_LE(line.size(), 130u * 1024);
    const auto replies = json::parse(line);
    ASSERT_EQ(replies.size(), 8u);
    EXPECT_TRUE(replies[0].contains("result"));
    EXPECT_TRUE(replies[1].contains("result"));
    EXPECT_EQ(replies[7]["id"], 8);
    EXPECT_EQ(replies[7]["error"]["code"], -32600);
    EXPECT_THAT(replies[7]["error"]["message"].get<std::string>(), HasSubstr("at most 131072"));
}

TEST_F(CapturesTest, StatusShowsTheWritersFigures) {
    auto status = call("status")["result"]["captures"];
    EXPECT_TRUE(status["file"].is_null()) << "memory only without a sink";
    FakeSink sink;
    sink.stats_value = {3, 2, std::string("cannot write: No space left on device")};
    dispatcher_.captures().set_sink(&sink);
    call("photo");
    ASSERT_EQ(sink.lines.size(), 1u);
    EXPECT_EQ(json::parse(sink.lines[0])["index"], 1);
    status = call("status")["result"]["captures"];
    EXPECT_EQ(status["written"], 3);
    EXPECT_EQ(status["dropped"], 2);
    EXPECT_EQ(status["error"], "cannot write: No space left on device");
    EXPECT_EQ(status["file"], "/var/lib/gportd/captures.jsonl");
}

TEST_F(CapturesTest, CaptureIsATopicLikeTheOthers) {
    auto subscribed = call("subscribe", {{"topics", {"capture"}}});
    EXPECT_EQ(subscribed["result"]["topics"], json::array({"capture"}));
    EXPECT_TRUE(client_.subscriptions.capture);
    call("unsubscribe");
    EXPECT_FALSE(client_.subscriptions.capture);
}

}  // namespace
}  // namespace gport::ipc
