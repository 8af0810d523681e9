// The pure JSON-RPC layer, driven line by line with a fake core.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "fake_api.hpp"
#include "gport/ipc/json_rpc.hpp"

namespace gport::ipc {
namespace {

using nlohmann::json;
using ::testing::HasSubstr;

class DispatcherTest : public ::testing::Test {
  protected:
    // Every reply line sent so far, parsed; checks each is one whole line.
    std::vector<json> send(std::string_view line) {
        const auto before = lines_.size();
        dispatcher_.handle_line(line, client_, [this](std::string reply) {
            EXPECT_FALSE(reply.empty());
            EXPECT_EQ(reply.back(), '\n');
            EXPECT_EQ(reply.find('\n'), reply.size() - 1) << "one line per reply";
            lines_.push_back(std::move(reply));
        });
        std::vector<json> out;
        for (auto i = before; i < lines_.size(); ++i) {
            out.push_back(json::parse(lines_[i]));
        }
        return out;
    }

    json call(std::string_view method, json params = nullptr) {
        json request = {{"jsonrpc", "2.0"}, {"id", 1}, {"method", method}};
        if (!params.is_null()) {
            request["params"] = std::move(params);
        }
        auto replies = send(request.dump());
        EXPECT_EQ(replies.size(), 1u) << request.dump();
        return replies.empty() ? json() : replies[0];
    }

    static int code(const json& reply) { return reply.at("error").at("code").get<int>(); }
    static std::string message(const json& reply) {
        return reply.at("error").at("message").get<std::string>();
    }

    testing::FakeApi api_;
    ClientState client_{{7, 4242, 1000, 1000, {}}, {}, 0, {}};
    Dispatcher dispatcher_{api_, [] { return ServerStats{3, 11}; }};
    std::vector<std::string> lines_;
};

TEST_F(DispatcherTest, EchoesIdsOfEveryAllowedTypeAndAlwaysSaysJsonRpc2) {
    for (const auto* id : {"1", "-5", "2.5", "\"abc\"", "null"}) {
        auto replies = send(fmt::format(R"({{"id":{},"method":"stop"}})", id));
        ASSERT_EQ(replies.size(), 1u);
        EXPECT_EQ(replies[0]["id"], json::parse(id));
        EXPECT_EQ(replies[0]["jsonrpc"], "2.0");
        EXPECT_EQ(replies[0]["result"]["sent"], true);
    }
}

TEST_F(DispatcherTest, RequestWithoutIdRunsButGetsNoReply) {
    EXPECT_TRUE(send(R"({"method":"photo"})").empty());
    EXPECT_TRUE(send(R"({"method":"no_such_method"})").empty());
    EXPECT_THAT(api_.calls, ::testing::ElementsAre("photo by 7"));
}

TEST_F(DispatcherTest, MalformedJsonIsAParseErrorWithNullId) {
    auto replies = send(R"({"id":1,"method":)");
    ASSERT_EQ(replies.size(), 1u);
    EXPECT_EQ(code(replies[0]), rpc_error::kParse);
    EXPECT_TRUE(replies[0]["id"].is_null());
    EXPECT_EQ(send(std::string("\xff\xfe\x00\x01garbage", 11)).at(0)["error"]["code"], -32700);
}

TEST_F(DispatcherTest, NumberTooLargeForADoubleIsAParseError) {
    // nlohmann reports it as out_of_range, not parse_error (found by request_fuzz).
    auto replies = send(R"({"id":1,"method":"speed","params":{"roll":1e999}})");
    ASSERT_EQ(replies.size(), 1u);
    EXPECT_EQ(code(replies[0]), rpc_error::kParse);
}

TEST_F(DispatcherTest, DeepNestingIsRefusedBeforeParsing) {
    const std::string deep(100000, '[');
    auto replies = send(deep);
    ASSERT_EQ(replies.size(), 1u);
    EXPECT_EQ(code(replies[0]), rpc_error::kParse);
    EXPECT_THAT(message(replies[0]), HasSubstr("nesting deeper than 64"));
    // Brackets inside strings do not count.
    auto ok =
        send(R"({"id":"[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[",)"
             R"("method":"center"})");
    EXPECT_EQ(ok.at(0)["result"]["sent"], true);
}

TEST_F(DispatcherTest, EnvelopeErrorsAreInvalidRequest) {
    EXPECT_EQ(code(send(R"([1])").at(0)[0]), rpc_error::kInvalidRequest);
    EXPECT_EQ(code(send(R"("hello")").at(0)), rpc_error::kInvalidRequest);
    EXPECT_EQ(code(send(R"({"id":1})").at(0)), rpc_error::kInvalidRequest);
    EXPECT_EQ(code(send(R"({"id":1,"method":5})").at(0)), rpc_error::kInvalidRequest);
    EXPECT_EQ(code(send(R"({"id":[1],"method":"stop"})").at(0)), rpc_error::kInvalidRequest);
    auto version = send(R"({"jsonrpc":"1.0","id":3,"method":"stop"})").at(0);
    EXPECT_EQ(code(version), rpc_error::kInvalidRequest);
    EXPECT_EQ(version["id"], 3);
    EXPECT_THAT(message(send(R"({"id":1,"method":"stop","extra":1})").at(0)),
                HasSubstr("allowed: jsonrpc, id, method and params"));
    EXPECT_THAT(
        message(send(fmt::format(R"({{"id":"{}","method":"stop"}})", std::string(200, 'x'))).at(0)),
        HasSubstr("limited to 128 bytes"));
}

TEST_F(DispatcherTest, UnknownMethodListsTheMethods) {
    auto reply = call("fly");
    EXPECT_EQ(code(reply), rpc_error::kUnknownMethod);
    EXPECT_THAT(message(reply), HasSubstr("\"fly\""));
    EXPECT_THAT(message(reply), HasSubstr("status, attitude, subscribe"));
}

TEST_F(DispatcherTest, StatusAddsServerFiguresAndThisClient) {
    api_.status_value.link = daemon::LinkState::kUp;
    api_.status_value.device = "/dev/gimbal";
    api_.status_value.device_open = true;
    api_.status_value.uptime = daemon::Millis(5000);
    api_.status_value.attitude_age = daemon::Millis(12);
    api_.status_value.counters.crc_errors = 4;
    api_.status_value.motion = daemon::MotionStatus{
        daemon::MotionMode::kSpeed, client_.info, {1000, 0, -250}, daemon::Millis(300)};
    api_.status_value.motion->elapsed = daemon::Millis(1200);
    client_.dropped = 2;
    auto result = call("status")["result"];
    EXPECT_EQ(result["link"]["state"], "up");
    EXPECT_EQ(result["device"], "/dev/gimbal");
    EXPECT_EQ(result["uptime_ms"], 5000);
    EXPECT_EQ(result["attitude_age_ms"], 12);
    EXPECT_EQ(result["counters"]["crc_errors"], 4);
    EXPECT_EQ(result["counters"]["dropped_notifications"], 11);
    EXPECT_EQ(result["clients"], 3);
    EXPECT_EQ(result["dropped_notifications"], 11);
    EXPECT_EQ(result["client"]["dropped"], 2);
    EXPECT_EQ(result["client"]["pid"], 4242);
    EXPECT_EQ(result["motion"]["mode"], "speed");
    EXPECT_EQ(result["motion"]["speed"]["roll"], 10.0);
    EXPECT_EQ(result["motion"]["speed"]["yaw"], -2.5);
    EXPECT_EQ(result["motion"]["time_left_ms"], 300);
    EXPECT_EQ(result["motion"]["elapsed_ms"], 1200);
    EXPECT_TRUE(result["controller"].is_null());
    EXPECT_TRUE(result.contains("api_version"));
    EXPECT_TRUE(result.contains("daemon_version"));
    EXPECT_EQ(code(call("status", {{"verbose", true}})), rpc_error::kInvalidParams);
}

TEST_F(DispatcherTest, AttitudeHasThePayloadAndAge) {
    EXPECT_EQ(code(call("attitude")), rpc_error::kLinkDown);
    daemon::AttitudeSample sample;
    sample.seq = 9;
    sample.received = std::chrono::steady_clock::now();
    sample.wall = daemon::WallTime(std::chrono::microseconds(1763770000123456));
    sample.attitude.imu = {0, 0, -3929};
    api_.attitude = sample;
    auto result = call("attitude")["result"];
    EXPECT_EQ(result["seq"], 9);
    EXPECT_EQ(result["imu"]["yaw"], -39.29);
    EXPECT_EQ(result["t"].dump(), "1763770000.123456");
    EXPECT_GE(result["age_ms"].get<int>(), 0);
    EXPECT_FALSE(result.contains("rates"));
}

TEST_F(DispatcherTest, SpeedConvertsUnitsAndSaysWhenItEnds) {
    auto result = call("speed", {{"roll", 12.345}, {"yaw", -3}, {"duration_ms", 2000}})["result"];
    EXPECT_EQ(result["duration_ms"], 2000);
    EXPECT_GT(result["ends_at"].get<double>(), 1.7e9);
    EXPECT_EQ(api_.calls.back(), "speed 1235 0 -300 2000 by 7");
    call("speed");
    EXPECT_EQ(api_.calls.back(), "speed 0 0 0 -1 by 7");
}

TEST_F(DispatcherTest, ClampIsPassedToTheCoreAndTheReplySaysWhatWasSent) {
    auto angle = call("angle", {{"pitch", -90}})["result"];
    EXPECT_EQ(api_.calls.back(), "angle 0 -9000 0 by 7");
    EXPECT_EQ(angle, json({{"sent", true},
                           {"angle", {{"roll", 0.0}, {"pitch", -90.0}, {"yaw", 0.0}}},
                           {"clamped", json::array()}}));
    api_.clamped = {"pitch"};
    angle = call("angle", {{"pitch", -90}, {"clamp", true}})["result"];
    EXPECT_EQ(api_.calls.back(), "angle 0 -9000 0 clamp by 7");
    EXPECT_EQ(angle["clamped"], json({"pitch"}));
    call("angle", {{"pitch", -90}, {"clamp", false}});
    EXPECT_EQ(api_.calls.back(), "angle 0 -9000 0 by 7");

    auto speed = call("speed", {{"yaw", 20}, {"clamp", true}})["result"];
    EXPECT_EQ(api_.calls.back(), "speed 0 0 2000 -1 clamp by 7");
    EXPECT_EQ(speed["speed"], json({{"roll", 0.0}, {"pitch", 0.0}, {"yaw", 20.0}}));
    EXPECT_EQ(speed["clamped"], json({"pitch"}));
    EXPECT_EQ(speed["braked"], json::array());
    EXPECT_TRUE(speed.contains("duration_ms"));
    api_.braked = {"roll", "yaw"};
    EXPECT_EQ(call("speed", {{"yaw", 20}})["result"]["braked"], json({"roll", "yaw"}));

    const auto calls = api_.calls.size();
    EXPECT_THAT(message(call("angle", {{"clamp", 1}})), HasSubstr("clamp must be true or false"));
    EXPECT_THAT(message(call("speed", {{"clamp", "yes"}})),
                HasSubstr("clamp must be true or false"));
    EXPECT_EQ(api_.calls.size(), calls);
}

TEST_F(DispatcherTest, ParamsAreValidatedNamingFieldAndRange) {
    auto range = call("speed", {{"pitch", 400}});
    EXPECT_EQ(code(range), rpc_error::kInvalidParams);
    EXPECT_THAT(message(range), HasSubstr("pitch"));
    EXPECT_THAT(message(range), HasSubstr("-327.67 to 327.67"));
    EXPECT_THAT(message(call("angle", {{"roll", "up"}})), HasSubstr("roll must be a number"));
    EXPECT_THAT(message(call("speed", {{"duration_ms", 0}})),
                HasSubstr("duration_ms must be an integer from 1"));
    EXPECT_THAT(message(call("speed", {{"duration_ms", 1.5}})), HasSubstr("duration_ms"));
    EXPECT_THAT(message(call("angle", {{"zoom", 1}})),
                HasSubstr("unknown parameter \"zoom\"; allowed: roll, pitch, yaw, clamp and wait"));
    EXPECT_THAT(message(call("stop", {{"now", 1}})), HasSubstr("takes no parameters"));
    EXPECT_THAT(message(call("stop", json::array({1}))), HasSubstr("params must be an object"));
    EXPECT_EQ(call("stop", json::array())["result"]["sent"], true);
    EXPECT_THAT(message(call("set_settings", {{"dead_zone", 256}})),
                HasSubstr("dead_zone must be an integer from 0 to 255"));
    EXPECT_THAT(message(call("set_settings", {{"inverted", "yes"}})),
                HasSubstr("inverted must be true or false"));
    EXPECT_THAT(message(call("set_settings", json::object())), HasSubstr("at least one of"));
    EXPECT_EQ(api_.calls.size(), 1u);  // only the "stop" with [] reached the core
}

// Both ranges end at the configured keepalive.max_duration_ms, and the
// refusal says so (it once said 86400000, a bound of the protocol's own).
TEST_F(DispatcherTest, DurationAndLeaseRefusalsNameTheConfiguredMaximum) {
    api_.max_duration_value = daemon::Millis(60000);
    for (const char* key : {"duration_ms", "lease_ms"}) {
        for (const json& value : {json(0), json(60001), json(100000000), json(1.5), json("x")}) {
            const auto reply = call("speed", {{key, value}});
            EXPECT_EQ(code(reply), rpc_error::kInvalidParams);
            EXPECT_EQ(message(reply), std::string(key) +
                                          " must be an integer from 1 to 60000 "
                                          "(keepalive.max_duration_ms)")
                << value;
        }
    }
    EXPECT_TRUE(api_.calls.empty());
    EXPECT_EQ(call("speed", {{"lease_ms", 60000}, {"duration_ms", 60000}})["result"]["duration_ms"],
              60000);
}

TEST_F(DispatcherTest, CoreErrorsMapToTheirCodes) {
    const std::pair<daemon::ErrorCode, int> cases[] = {
        {daemon::ErrorCode::kInvalidParams, -32602}, {daemon::ErrorCode::kLinkDown, -32000},
        {daemon::ErrorCode::kPermission, -32001},    {daemon::ErrorCode::kNoAnswer, -32002},
        {daemon::ErrorCode::kBusy, -32003},          {daemon::ErrorCode::kTooManyRequests, -32005},
    };
    for (const auto& [error, expected] : cases) {
        api_.error = daemon::CommandError{error, "from the core"};
        for (const auto* method : {"speed", "stop", "angle", "center", "lock", "photo", "record",
                                   "acquire", "release"}) {
            auto reply = call(method);
            EXPECT_EQ(code(reply), expected) << method;
            EXPECT_EQ(message(reply), "from the core");
        }
    }
}

TEST_F(DispatcherTest, EveryCameraAndModeCommandReachesTheCore) {
    for (const auto* method : {"stop", "center", "lock", "photo"}) {
        EXPECT_EQ(call(method)["result"]["sent"], true);
        EXPECT_EQ(api_.calls.back(), fmt::format("{} by 7", method));
    }
    EXPECT_EQ(call("record")["result"]["sent"], true);
    EXPECT_EQ(api_.calls.back(), "record toggle - by 7");
    call("angle", {{"pitch", -90}});
    EXPECT_EQ(api_.calls.back(), "angle 0 -9000 0 by 7");
}

TEST_F(DispatcherTest, RecordPassesOnAndForceAndSaysTheAssumedState) {
    api_.record_result = {false, daemon::RecordingState::kOn};
    auto r = call("record", {{"on", true}})["result"];
    EXPECT_EQ(r, (json{{"sent", false}, {"recording", "on"}}));
    EXPECT_EQ(api_.calls.back(), "record on - by 7");
    api_.record_result = {true, daemon::RecordingState::kOff};
    r = call("record", {{"on", false}, {"force", true}})["result"];
    EXPECT_EQ(r["sent"], true);
    EXPECT_EQ(r["recording"], "off");
    EXPECT_EQ(r["capture"]["kind"], "record_stop") << "a toggle sent is a capture";
    EXPECT_EQ(api_.calls.back(), "record off force by 7");
    api_.record_result = {true, daemon::RecordingState::kUnknown};
    EXPECT_EQ(call("record", json::object())["result"]["recording"], "unknown");
    EXPECT_EQ(api_.calls.back(), "record toggle - by 7");
}

TEST_F(DispatcherTest, RecordRefusesBadParamsBeforeTheCore) {
    const auto before = api_.calls.size();
    EXPECT_EQ(code(call("record", {{"on", "yes"}})), -32602);
    EXPECT_EQ(code(call("record", {{"on", true}, {"force", 1}})), -32602);
    EXPECT_EQ(code(call("record", {{"state", "on"}})), -32602);
    auto alone = call("record", {{"force", true}});
    EXPECT_EQ(code(alone), -32602);
    EXPECT_THAT(message(alone), HasSubstr("force needs on"));
    EXPECT_EQ(api_.calls.size(), before);
}

TEST_F(DispatcherTest, StatusSaysTheAssumedRecordingState) {
    EXPECT_EQ(call("status")["result"]["recording"], "unknown");
    api_.status_value.recording = daemon::RecordingState::kOn;
    dispatcher_.invalidate_status();  // what the server does on the core's events
    EXPECT_EQ(call("status")["result"]["recording"], "on");
}

TEST_F(DispatcherTest, LimitsReportsTheConfiguredSoftLimits) {
    api_.limits_value.pitch = {-90, 30};
    api_.limits_value.max_speed = 60;
    auto result = call("limits")["result"];
    EXPECT_EQ(result["pitch"], (json{{"min", -90.0}, {"max", 30.0}}));
    EXPECT_EQ(result["roll"], (json{{"min", -327.67}, {"max", 327.67}}));
    EXPECT_EQ(result["yaw"]["max"], 327.67);
    EXPECT_EQ(result["max_speed"], 60.0);
    EXPECT_EQ(result["braking_margin_deg"], 1.0);
    EXPECT_EQ(code(call("limits", {{"axis", "pitch"}})), rpc_error::kInvalidParams);
}

TEST_F(DispatcherTest, AcquireAndReleaseSayWhoHoldsControl) {
    auto held = call("acquire")["result"];
    EXPECT_EQ(held["controller"]["pid"], 4242);
    EXPECT_EQ(held["you_hold_control"], true);
    auto released = call("release")["result"];
    EXPECT_TRUE(released["controller"].is_null());
    EXPECT_EQ(released["you_hold_control"], false);
}

TEST_F(DispatcherTest, SettingsAnswerLaterThroughTheSink) {
    EXPECT_TRUE(send(R"({"id":5,"method":"get_settings"})").empty());
    api_.run_settings();
    ASSERT_EQ(lines_.size(), 1u);
    auto got = json::parse(lines_[0]);
    EXPECT_EQ(got["id"], 5);
    EXPECT_EQ(got["result"], json({{"dead_zone", 10}, {"follow_speed", 20}, {"inverted", false}}));

    send(R"({"id":6,"method":"set_settings","params":{"follow_speed":99,"inverted":true}})");
    api_.run_settings();
    auto set = json::parse(lines_.back());
    EXPECT_EQ(set["result"]["follow_speed"], 99);
    EXPECT_EQ(set["result"]["inverted"], true);
    EXPECT_EQ(api_.calls.back(), "set_settings -1 99 1 by 7");

    api_.error = daemon::CommandError{daemon::ErrorCode::kNoAnswer, "the gimbal did not answer"};
    send(R"({"id":7,"method":"get_settings"})");
    api_.run_settings();
    EXPECT_EQ(json::parse(lines_.back())["error"]["code"], -32002);
}

TEST_F(DispatcherTest, SubscriptionsChangeTheClientState) {
    auto result = call("subscribe", {{"topics", {"attitude", "link"}}, {"max_rate_hz", 5}});
    EXPECT_EQ(result["result"]["topics"], json({"attitude", "link"}));
    EXPECT_EQ(result["result"]["max_rate_hz"], 5.0);
    EXPECT_TRUE(client_.subscriptions.attitude && client_.subscriptions.link);
    EXPECT_EQ(client_.subscriptions.max_rate_hz, 5.0);
    auto left = call("unsubscribe", {{"topics", {"attitude"}}})["result"];
    EXPECT_EQ(left["topics"], json({"link"}));
    EXPECT_FALSE(client_.subscriptions.max_rate_hz);
    call("subscribe", {{"topics", {"motion"}}});
    EXPECT_EQ(call("unsubscribe")["result"]["topics"], json::array());
    EXPECT_THAT(
        message(call("subscribe", {{"topics", {"weather"}}})),
        HasSubstr("topics must be a non-empty array of attitude, link, motion and capture"));
    EXPECT_THAT(message(call("subscribe", {{"topics", {"attitude"}}, {"max_rate_hz", 0}})),
                HasSubstr("max_rate_hz = 0 is out of range; allowed 0.01 to 1000"));
    EXPECT_THAT(message(call("subscribe")), HasSubstr("topics is required"));
}

// 1e-12 Hz overflowed a duration cast; 1e-9 Hz never sent its first sample.
TEST_F(DispatcherTest, TinyMaxRateIsRefusedNamingTheRange) {
    for (double rate : {1e-12, 1e-9, 0.0099}) {
        auto reply = call("subscribe", {{"topics", {"attitude"}}, {"max_rate_hz", rate}});
        EXPECT_EQ(code(reply), -32602) << rate;
        EXPECT_THAT(message(reply), HasSubstr("allowed 0.01 to 1000")) << rate;
    }
    EXPECT_FALSE(client_.subscriptions.attitude);
    auto ok = call("subscribe", {{"topics", {"attitude"}}, {"max_rate_hz", 0.01}});
    EXPECT_EQ(ok["result"]["max_rate_hz"], 0.01);
}

TEST_F(DispatcherTest, RequestsOverTheRateGetTooManyAndDoNotRun) {
    client_.rate = RequestRate(5);
    json batch = json::array();
    for (int i = 1; i <= 8; ++i) {
        batch.push_back({{"id", i}, {"method", "photo"}});
    }
    auto replies = send(batch.dump());
    ASSERT_EQ(replies.size(), 1u);
    ASSERT_EQ(replies[0].size(), 8u);
    // Five tokens; a request that held the loop past RequestRate::kCostPerToken
    // (a loaded machine) costs more than one, so fewer may run.
    std::size_t sent = 0;
    for (int i = 0; i < 8; ++i) {
        if (replies[0][i].contains("result")) {
            EXPECT_EQ(replies[0][i]["result"]["sent"], true) << i;
            EXPECT_EQ(sent, static_cast<std::size_t>(i)) << "the accepted ones come first";
            ++sent;
            continue;
        }
        EXPECT_EQ(code(replies[0][i]), -32005) << i;
        EXPECT_THAT(message(replies[0][i]), HasSubstr("5 per second (socket.max_requests_per_s)"));
    }
    EXPECT_LE(sent, 5u);
    EXPECT_GE(sent, 1u) << "under qemu a request may cost several tokens";
    EXPECT_EQ(api_.calls.size(), sent) << "refused requests are not carried out";
}

// A request's cost on the event loop is charged on top of its token: one
// token per millisecond beyond the first, down to one second's worth of debt.
TEST(RequestRate, CostIsChargedAsDebtThatRequestsWaitOut) {
    RequestRate rate(100);
    const auto t0 = std::chrono::steady_clock::time_point{} + std::chrono::seconds(100);
    ASSERT_TRUE(rate.take(t0));
    rate.charge(std::chrono::microseconds(900), t0);
    EXPECT_TRUE(rate.has_token(t0)) << "a request within the budget costs its one token";
    rate.charge(std::chrono::milliseconds(500), t0);
    EXPECT_FALSE(rate.has_token(t0)) << "500 ms of loop time is 499 tokens, capped at 100 of debt";
    EXPECT_GT(rate.wait_for(1, t0), std::chrono::seconds(1));
    EXPECT_FALSE(rate.take(t0 + std::chrono::milliseconds(900)));
    EXPECT_TRUE(rate.take(t0 + std::chrono::milliseconds(1100)));
}

TEST_F(DispatcherTest, StatusNamesTheLongestRequest) {
    call("photo");
    const auto loop = call("status")["result"]["loop"];
    EXPECT_TRUE(loop["worst_request_us"].is_number_unsigned());
    EXPECT_TRUE(loop["worst_method"].is_string());
    const auto camera = call("status")["result"]["camera"];
    EXPECT_TRUE(camera.contains("max_commands_per_s"));
    EXPECT_TRUE(camera.contains("refused"));
}

TEST_F(DispatcherTest, BatchesAnswerInOrderInOneLine) {
    auto replies = send(R"([{"id":1,"method":"stop"},{"method":"photo"},)"
                        R"({"id":2,"method":"get_settings"},{"id":3,"method":"nope"},5])");
    EXPECT_TRUE(replies.empty()) << "waits for the settings answer";
    api_.run_settings();
    ASSERT_EQ(lines_.size(), 1u);
    auto batch = json::parse(lines_[0]);
    ASSERT_EQ(batch.size(), 4u);
    EXPECT_EQ(batch[0]["id"], 1);
    EXPECT_EQ(batch[1]["id"], 2);
    EXPECT_EQ(batch[1]["result"]["dead_zone"], 10);
    EXPECT_EQ(batch[2]["error"]["code"], -32601);
    EXPECT_EQ(batch[3]["error"]["code"], -32600);
    EXPECT_TRUE(send(R"([{"method":"photo"},{"method":"record"}])").empty());
    EXPECT_EQ(code(send("[]").at(0)), rpc_error::kInvalidRequest);
    std::string big = "[";
    for (int i = 0; i < 33; ++i) {
        big += std::string(i ? "," : "") + R"({"id":1,"method":"stop"})";
    }
    EXPECT_THAT(message(send(big + "]").at(0)), HasSubstr("1 to 32 requests"));
}

}  // namespace
}  // namespace gport::ipc
