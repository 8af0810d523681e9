// AsyncClient's JSON-text interface (async_call_json, on_notification_json,
// on_notification_text) against gportd --simulate: results and refusals as
// text, the checks made before sending, and the notification lines as
// gportd wrote them.
#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <nlohmann/json.hpp>

#include "client_fixture.hpp"
#include "gport/client/async_client.hpp"

namespace gport::testing {
namespace {

namespace asio = boost::asio;
using nlohmann::json;

class AsyncJsonTest : public SimulatedDaemonTest {
  protected:
    void SetUp() override {
        SimulatedDaemonTest::SetUp();
        bool done = false;
        client_json_.async_connect(socket(), [&](std::optional<gc::Error> error) {
            EXPECT_FALSE(error);
            done = true;
        });
        ASSERT_TRUE(run_until([&] { return done; }));
    }

    // Runs the loop until `done()` or 10 s.
    bool run_until(const std::function<bool()>& done) {
        asio::steady_timer guard(io_, 10s);
        guard.async_wait([&](boost::system::error_code ec) {
            if (!ec) {
                io_.stop();
            }
        });
        while (!done() && !io_.stopped()) {
            io_.run_one();
        }
        guard.cancel();
        io_.restart();
        io_.poll();
        io_.restart();
        return done();
    }

    // One call's error and result text.
    std::pair<std::optional<gc::Error>, std::string> call(const std::string& method,
                                                          const std::string& params) {
        std::optional<std::pair<std::optional<gc::Error>, std::string>> out;
        client_json_.async_call_json(method, params, [&](auto error, std::string result) {
            out.emplace(std::move(error), std::move(result));
        });
        EXPECT_TRUE(run_until([&] { return out.has_value(); }));
        return out.value_or(std::make_pair(std::nullopt, std::string()));
    }

    asio::io_context io_;
    gc::AsyncClient client_json_{io_};
};

TEST_F(AsyncJsonTest, UnknownMethodsAndParamsThatAreNoObjectAreRefusedUnsent) {
    auto [error, result] = call("reboot", "{}");
    ASSERT_TRUE(error);
    EXPECT_TRUE(error->is(gc::ErrorCode::kInvalidParams));
    EXPECT_NE(error->message().find("reboot"), std::string::npos);
    EXPECT_TRUE(result.empty());

    for (const std::string params : {"[1,2]", "42", "{\"yaw\":", "null"}) {
        auto [e, r] = call("speed", params);
        ASSERT_TRUE(e) << params;
        EXPECT_TRUE(e->is(gc::ErrorCode::kInvalidParams)) << params;
        EXPECT_NE(e->message().find("JSON object"), std::string::npos) << e->message();
    }
    auto [channel, unused] = call("attitude_channel", "");
    ASSERT_TRUE(channel);
    EXPECT_TRUE(channel->is(gc::ErrorCode::kInvalidParams));
    // Nothing was sent: the gimbal never moved.
    EXPECT_FALSE(client().status().motion);
}

TEST_F(AsyncJsonTest, ResultsComeAsJsonTextAndRefusalsWithGportdsCode) {
    auto [error, result] = call("status", "");
    ASSERT_FALSE(error) << error->what();
    const auto status = json::parse(result);
    EXPECT_EQ(status.at("link").at("state"), "up");

    auto [moved, speed] = call("speed", R"({"yaw":10,"duration_ms":3000})");
    ASSERT_FALSE(moved) << moved->what();
    EXPECT_EQ(json::parse(speed).at("speed").at("yaw"), 10);
    const auto motion = client().status().motion;
    ASSERT_TRUE(motion);
    EXPECT_EQ(motion->mode, "speed");
    auto [stopped, stop] = call("stop", "{}");
    EXPECT_FALSE(stopped);

    auto [refused, none] = call("speed", R"({"yaw":"fast"})");
    ASSERT_TRUE(refused);
    EXPECT_TRUE(refused->is(gc::ErrorCode::kInvalidParams)) << refused->what();
    EXPECT_TRUE(none.empty());
}

TEST_F(AsyncJsonTest, NotificationLinesComeWholeInOrderBesideTheTypedOnes) {
    std::vector<std::string> lines;
    int typed = 0;
    client_json_.on_notification_json([&](const std::string& line) { lines.push_back(line); });
    client_json_.on_notification([&](const gc::Notification&) { ++typed; });
    auto [error, result] = call("subscribe", R"({"topics":["attitude"],"max_rate_hz":20})");
    ASSERT_FALSE(error) << error->what();
    ASSERT_TRUE(run_until([&] { return lines.size() >= 5 && typed >= 5; }));
    std::uint64_t last = 0;
    for (const auto& line : lines) {
        EXPECT_NE(line.back(), '\n');
        const auto message = json::parse(line);
        EXPECT_EQ(message.at("jsonrpc"), "2.0");
        EXPECT_EQ(message.at("method"), "attitude");
        const auto seq = message.at("params").at("seq").get<std::uint64_t>();
        EXPECT_GT(seq, last);
        last = seq;
    }
}

// on_notification_text (1.9.0): each line with its topic, read by the
// library: a relay routes it without searching the text.
TEST_F(AsyncJsonTest, NotificationLinesComeWithTheirTopic) {
    std::vector<std::pair<std::string, std::string>> lines;
    client_json_.on_notification_text([&](const std::string& topic, const std::string& line) {
        lines.emplace_back(topic, line);
    });
    auto [error, result] = call("subscribe", R"({"topics":["attitude","link"],"max_rate_hz":20})");
    ASSERT_FALSE(error) << error->what();
    ASSERT_TRUE(run_until([&] { return lines.size() >= 3; }));
    for (const auto& [topic, line] : lines) {
        EXPECT_EQ(json::parse(line).at("method"), topic) << line;
    }
    EXPECT_EQ(lines.back().first, "attitude");
}

}  // namespace
}  // namespace gport::testing
