// The blocking Client's JSON-text interface (call_json, call_json_response,
// on_notification_json) and its interruption (set_interrupt), against
// gportd --simulate: what gportctl is built on.
#include <gmock/gmock.h>

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>

#include "client_fixture.hpp"
#include "gport/client/results.hpp"

namespace gport::testing {
namespace {

using nlohmann::json;
using ClientJson = SimulatedDaemonTest;

TEST_F(ClientJson, RefusesBeforeSendingWhatIsNoRequest) {
    for (const auto& [method, params] : std::vector<std::pair<std::string, std::string>>{
             {"", "{}"},
             {std::string(65, 'a'), "{}"},
             {"sta tus", "{}"},
             {"status", "5"},
             {"status", "\"x\""},
             {"status", "{"},
             {"status", std::string(100, '[') + std::string(100, ']')}}) {
        try {
            client().call_json(method, params);
            ADD_FAILURE() << method << " " << params << " was sent";
        } catch (const gc::Error& e) {
            EXPECT_TRUE(e.is(gc::ErrorCode::kInvalidParams)) << e.what();
            EXPECT_NE(e.message().find("nothing was sent"), std::string::npos) << e.message();
        }
    }
    EXPECT_TRUE(client().connected());
    EXPECT_EQ(json::parse(client().call_json("status"))["link"]["state"], "up");
}

TEST_F(ClientJson, ResultsAndRefusalsAsText) {
    const auto limits = json::parse(client().call_json("limits"));
    EXPECT_TRUE(limits.contains("braking_margin_deg"));
    // An unknown method is gportd's to refuse: -32601, thrown by call_json,
    // returned whole by call_json_response.
    EXPECT_EQ(error_code_of([&] { client().call_json("fly"); }), -32601);
    const auto response = json::parse(client().call_json_response("fly", "{}"));
    EXPECT_EQ(response["error"]["code"], -32601);
    EXPECT_TRUE(response.contains("id"));
    const auto angle = json::parse(client().call_json_response("angle", R"({"pitch": "down"})"));
    EXPECT_EQ(angle["error"]["code"], -32602);
    const auto ok = json::parse(client().call_json_response("get_settings"));
    EXPECT_TRUE(ok["result"].contains("dead_zone"));
}

// results.hpp: the text call_json returns, decoded as the typed calls
// decode it, gives what they give.
TEST_F(ClientJson, ResultsDecodedFromTextAreTheTypedCallsResults) {
    const auto typed = client().status();
    const auto text = gc::status_from_json(client().call_json("status"));
    EXPECT_EQ(text.link.state, typed.link.state);
    EXPECT_EQ(text.device, typed.device);
    EXPECT_EQ(text.api_version, typed.api_version);
    EXPECT_EQ(text.daemon_version, typed.daemon_version);
    EXPECT_GE(text.uptime_ms, typed.uptime_ms);
    EXPECT_GE(text.counters.frames_in, typed.counters.frames_in);
    const auto limits = gc::limits_from_json(client().call_json("limits"));
    EXPECT_EQ(limits.max_speed, client().limits().max_speed);
    EXPECT_EQ(limits.pitch.min, client().limits().pitch.min);
    const auto settings = gc::settings_from_json(client().call_json("get_settings"));
    EXPECT_EQ(settings.dead_zone, client().settings().dead_zone);
    EXPECT_GT(gc::attitude_from_json(client().call_json("attitude")).seq, 0U);
    const auto angle = gc::angle_result_from_json(client().call_json("angle", R"({"pitch": -10})"));
    EXPECT_TRUE(angle.sent);
    EXPECT_DOUBLE_EQ(angle.angle.pitch, -10);
    EXPECT_EQ(
        gc::speed_result_from_json(client().call_json("speed", R"({"yaw": 5, "duration_ms": 200})"))
            .duration_ms,
        200);
    const auto link = gc::notification_from_json(
        R"({"jsonrpc":"2.0","method":"link","params":{"state":"up","reason":"ok"}})");
    ASSERT_TRUE(link.has_value());
    EXPECT_EQ(std::get<gc::LinkEvent>(*link).state, "up");
    EXPECT_FALSE(gc::notification_from_json(R"({"method":"capture","params":{}})").has_value());
}

// A result that is not what the type needs is Error kBadReply naming it and
// what was wrong, never a default-filled value or another exception.
TEST(ResultsFromJson, WhatDoesNotDecodeIsABadReplyNamingIt) {
    const auto bad_reply = [](const std::function<void()>& decode) -> std::string {
        try {
            decode();
        } catch (const gc::Error& e) {
            EXPECT_TRUE(e.is(gc::ErrorCode::kBadReply)) << e.what();
            return e.message();
        } catch (const std::exception& e) {
            ADD_FAILURE() << "not a gport::client::Error: " << e.what();
        }
        return "decoded";
    };
    EXPECT_THAT(bad_reply([] { gc::status_from_json("{\"link\":"); }),
                ::testing::HasSubstr("a status result that is not JSON"));
    EXPECT_THAT(bad_reply([] { gc::status_from_json("[1]"); }),
                ::testing::HasSubstr("not an object"));
    EXPECT_THAT(bad_reply([] { gc::status_from_json(R"({"uptime_ms": 5})"); }),
                ::testing::HasSubstr("status"));
    EXPECT_THAT(bad_reply([] { gc::status_from_json(R"({"link": {}, "uptime_ms": "long"})"); }),
                ::testing::HasSubstr("status"));
    EXPECT_THAT(bad_reply([] { gc::settings_from_json(R"({"dead_zone": 1})"); }),
                ::testing::HasSubstr("settings result"));
    EXPECT_THAT(bad_reply([] { gc::notification_from_json("5"); }),
                ::testing::HasSubstr("not an object"));
    EXPECT_THAT(bad_reply([] {
                    gc::notification_from_json(R"({"method":"attitude","params":{"seq":1}})");
                }),
                ::testing::HasSubstr("attitude notification"));
}

// The open descriptors of this process.
std::size_t descriptors_now() {
    std::size_t n = 0;
    for ([[maybe_unused]] const auto& entry :
         std::filesystem::directory_iterator("/proc/self/fd")) {
        ++n;
    }
    return n;
}

TEST_F(ClientJson, AttitudeChannelByTextClosesItsDescriptors) {
    client().call_json_response("attitude_channel");  // the first maps the block
    const auto before = descriptors_now();
    for (int i = 0; i < 50; ++i) {
        const auto reply = json::parse(client().call_json_response("attitude_channel"));
        ASSERT_TRUE(reply.contains("result")) << reply.dump();
    }
    EXPECT_LE(descriptors_now(), before + 2) << "no descriptor kept per call";
    EXPECT_EQ(client().status().link.state, "up") << "the connection is still usable";
}

TEST_F(ClientJson, NotificationsAsTextBesideTheTypedOnes) {
    std::vector<json> lines;
    std::size_t typed = 0;
    client().on_notification_json(
        [&](const std::string& text) { lines.push_back(json::parse(text)); });
    client().on_notification([&](const gc::Notification&) { ++typed; });
    client().call_json("subscribe", R"({"topics": ["attitude", "link"], "max_rate_hz": 20})");
    client().dispatch(500ms);
    ASSERT_FALSE(lines.empty());
    EXPECT_EQ(lines.front()["jsonrpc"], "2.0");
    EXPECT_EQ(lines.front()["method"], "attitude");
    EXPECT_TRUE(lines.front()["params"].contains("imu"));
    EXPECT_GE(typed, lines.size() - 1) << "the typed callback gets them too";
    client().on_notification_json({});
    lines.clear();
    client().dispatch(200ms);
    EXPECT_TRUE(lines.empty()) << "an empty function turns it off";
}

TEST_F(ClientJson, SharedMemorySamplesComeAsTheSocketWouldCarryThem) {
    std::vector<json> lines;
    client().on_notification_json(
        [&](const std::string& text) { lines.push_back(json::parse(text)); });
    client().subscribe({"attitude"}, gc::SubscribeOptions{.shared_memory = true});
    ASSERT_TRUE(eventually([&] {
        client().dispatch(100ms);
        return !lines.empty();
    }));
    EXPECT_EQ(lines.front()["method"], "attitude");
    EXPECT_TRUE(lines.front()["params"]["hall"].contains("yaw"));
}

TEST_F(ClientJson, AnInterruptEndsAWaitAndLeavesTheConnection) {
    bool stop = false;
    client().set_interrupt([&] { return stop; });
    client().call_json("subscribe", R"({"topics": ["attitude"]})");
    stop = true;
    // What the subscribe's reply brought with it (attitude samples read in the
    // same read) is still handed out; the interrupt ends the wait after it.
    const auto start = std::chrono::steady_clock::now();
    client().dispatch(10s);
    EXPECT_LT(std::chrono::steady_clock::now() - start, 5s) << "returns at once";
    int code = 0;
    for (int taken = 0; code == 0 && taken < 1000; ++taken) {
        code = error_code_of([&] { client().next_notification(); });
    }
    EXPECT_EQ(code, static_cast<int>(gc::ErrorCode::kInterrupted));
    // A call waiting for its reply: interrupted, the late reply dropped.
    EXPECT_EQ(error_code_of([&] { client().call_json("center", R"({"wait": true})"); }),
              static_cast<int>(gc::ErrorCode::kInterrupted));
    client().set_interrupt({});
    EXPECT_TRUE(client().connected());
    EXPECT_EQ(client().status().link.state, "up");
}

}  // namespace
}  // namespace gport::testing
