// The cached part of `status`: its age bound, what invalidates it, and the
// caller's own `client` member, which is never cached.
#include "gport/ipc/status_cache.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <nlohmann/json.hpp>
#include <string>

#include "fake_api.hpp"
#include "gport/ipc/json_rpc.hpp"

namespace gport::ipc {
namespace {

using nlohmann::json;
using namespace std::chrono_literals;

TEST(StatusCache, RebuildsOnlyOnceMaxAgeHasPassedOrWhenInvalidated) {
    StatusCache cache(5ms);
    int built = 0;
    const auto build = [&] { return "\"n\":" + std::to_string(++built); };
    const StatusCache::Clock::time_point t0{1s};
    EXPECT_EQ(cache.members(t0, build), "\"n\":1");
    EXPECT_EQ(cache.members(t0 + 4999us, build), "\"n\":1");
    EXPECT_EQ(cache.members(t0 + 5ms, build), "\"n\":2");
    cache.invalidate();
    EXPECT_EQ(cache.members(t0 + 5ms, build), "\"n\":3");
    EXPECT_EQ(cache.members(t0 + 1ms, build), "\"n\":4") << "a clock going back rebuilds";
    EXPECT_EQ(cache.builds(), 4u);
}

TEST(StatusCache, ZeroMaxAgeRebuildsEveryTime) {
    StatusCache cache(StatusCache::Clock::duration::zero());
    int built = 0;
    const auto build = [&] { return std::to_string(++built); };
    const StatusCache::Clock::time_point t0{1s};
    EXPECT_EQ(cache.members(t0, build), "1");
    EXPECT_EQ(cache.members(t0, build), "2");
}

class StatusCacheDispatcherTest : public ::testing::Test {
  protected:
    json status(ClientState& client) {
        json reply;
        dispatcher_.handle_line(R"({"jsonrpc":"2.0","id":1,"method":"status"})", client,
                                [&](std::string line) { reply = json::parse(line); });
        return reply.at("result");
    }

    testing::FakeApi api_;
    ClientState alice_{{7, 4242, 1000, 1000, {}}, {}, 0, {}};
    ClientState bob_{{8, 4343, 1001, 1001, {}}, {}, 0, {}};
    // An hour: nothing here expires by time, so the test needs no clock.
    Dispatcher dispatcher_{api_, [] { return ServerStats{2, 0}; }, std::chrono::hours(1)};
};

TEST_F(StatusCacheDispatcherTest, EachCallerGetsItsOwnExactClientPartFromOneBuild) {
    alice_.dropped = 3;
    bob_.dropped = 9;
    const auto a = status(alice_);
    const auto b = status(bob_);
    EXPECT_EQ(a["client"]["pid"], 4242);
    EXPECT_EQ(a["client"]["dropped"], 3);
    EXPECT_EQ(b["client"]["pid"], 4343);
    EXPECT_EQ(b["client"]["dropped"], 9);
    bob_.dropped = 10;
    EXPECT_EQ(status(bob_)["client"]["dropped"], 10) << "the caller's part is never cached";
    EXPECT_EQ(dispatcher_.status_cache().builds(), 1u);
    EXPECT_EQ(a["clients"], 2);
    EXPECT_EQ(a.size(), b.size());
}

TEST_F(StatusCacheDispatcherTest, SharedPartIsCachedUntilAnotherRequestOrAnEvent) {
    EXPECT_EQ(status(alice_)["recording"], "unknown");
    api_.status_value.recording = daemon::RecordingState::kOn;
    EXPECT_EQ(status(alice_)["recording"], "unknown") << "within max_age: the cached document";
    dispatcher_.handle_line(R"({"jsonrpc":"2.0","id":2,"method":"limits"})", bob_,
                            [](const std::string&) {});
    EXPECT_EQ(status(alice_)["recording"], "on") << "any other request invalidates it";
    api_.status_value.recording = daemon::RecordingState::kOff;
    dispatcher_.invalidate_status();
    EXPECT_EQ(status(alice_)["recording"], "off");
}

TEST_F(StatusCacheDispatcherTest, BatchesOfStatusStillAnswerEveryMember) {
    json reply;
    dispatcher_.handle_line(
        R"([{"jsonrpc":"2.0","id":1,"method":"status"},{"jsonrpc":"2.0","method":"status"},)"
        R"({"jsonrpc":"2.0","id":3,"method":"status"}])",
        alice_, [&](std::string line) { reply = json::parse(line); });
    ASSERT_TRUE(reply.is_array());
    ASSERT_EQ(reply.size(), 2u);
    EXPECT_EQ(reply[0]["id"], 1);
    EXPECT_EQ(reply[1]["id"], 3);
    EXPECT_EQ(reply[1]["result"]["client"]["pid"], 4242);
}

}  // namespace
}  // namespace gport::ipc
