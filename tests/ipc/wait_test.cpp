// angle and center with `wait`: the reply waits for the tracked motion's end
// (here ended by hand through the fake core) and says how it ended.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "fake_api.hpp"
#include "gport/ipc/json_rpc.hpp"
#include "server_harness.hpp"
#include "test_client.hpp"

namespace gport::ipc {
namespace {

using nlohmann::json;
using ::testing::HasSubstr;
using testing::ServerHarness;
using testing::TestClient;

daemon::AttitudeSample sample_at(protocol::Axes hall) {
    daemon::AttitudeSample s;
    s.seq = 42;
    s.received = std::chrono::steady_clock::now();
    s.wall = daemon::WallTime(std::chrono::microseconds(1763770000123456));
    s.attitude.hall = hall;
    return s;
}

daemon::MotionEnd reached_at(protocol::Axes hall) {
    return {daemon::EndReason::kReached, sample_at(hall), daemon::Millis(1234)};
}

class WaitDispatcherTest : public ::testing::Test {
  protected:
    std::vector<json> send(std::string_view line) {
        const auto before = replies_.size();
        dispatcher_.handle_line(
            line, client_, [this](std::string reply) { replies_.push_back(json::parse(reply)); });
        return {replies_.begin() + static_cast<std::ptrdiff_t>(before), replies_.end()};
    }

    testing::FakeApi api_;
    ClientState client_{{7, 4242, 1000, 1000, {}}, {}, 0, {}};
    Dispatcher dispatcher_{api_, [] { return ServerStats{1, 0}; }};
    std::vector<json> replies_;
};

TEST_F(WaitDispatcherTest, WaitMustBeABooleanAndIsCheckedBeforeTheCore) {
    for (const auto* line : {R"({"id":1,"method":"angle","params":{"pitch":10,"wait":1}})",
                             R"({"id":2,"method":"center","params":{"wait":"yes"}})",
                             R"({"id":3,"method":"center","params":{"wait":null}})"}) {
        auto replies = send(line);
        ASSERT_EQ(replies.size(), 1u) << line;
        EXPECT_EQ(replies[0]["error"]["code"], rpc_error::kInvalidParams);
        EXPECT_THAT(replies[0]["error"]["message"].get<std::string>(), HasSubstr("wait"));
    }
    EXPECT_TRUE(api_.calls.empty());
    auto other = send(R"({"id":4,"method":"lock","params":{"wait":true}})");
    EXPECT_EQ(other[0]["error"]["code"], rpc_error::kInvalidParams) << "lock takes no wait";
}

TEST_F(WaitDispatcherTest, ARefusedCommandAnswersAtOnceAndLeavesNoWaiter) {
    api_.error = daemon::CommandError{daemon::ErrorCode::kBusy, "another client holds control"};
    auto replies = send(R"({"id":1,"method":"angle","params":{"pitch":10,"wait":true}})");
    ASSERT_EQ(replies.size(), 1u);
    EXPECT_EQ(replies[0]["error"]["code"], rpc_error::kBusy);
    EXPECT_TRUE(api_.waiters.empty());
}

TEST_F(WaitDispatcherTest, TheReplyWaitsForTheEndAndSaysHowItEnded) {
    EXPECT_TRUE(send(R"({"id":5,"method":"angle","params":{"pitch":-30,"wait":true}})").empty());
    EXPECT_EQ(api_.calls.back(), "angle 0 -3000 0 wait by 7");
    ASSERT_EQ(api_.waiters.size(), 1u);
    api_.end_waiter(reached_at({0, -2990, 0}));
    ASSERT_EQ(replies_.size(), 1u);
    const auto& reply = replies_[0];
    EXPECT_EQ(reply["id"], 5);
    const auto& result = reply["result"];
    EXPECT_EQ(result["sent"], true);
    EXPECT_EQ(result["angle"]["pitch"], -30.0);
    EXPECT_EQ(result["clamped"], json::array());
    EXPECT_EQ(result["ended"]["reason"], "reached");
    EXPECT_EQ(result["ended"]["elapsed_ms"], 1234);
    const auto& attitude = result["ended"]["attitude"];
    EXPECT_EQ(attitude["seq"], 42);
    EXPECT_EQ(attitude["hall"]["pitch"], -29.9);
    EXPECT_TRUE(attitude.contains("age_ms"));
    EXPECT_TRUE(attitude.contains("t"));
}

TEST_F(WaitDispatcherTest, CenterWithoutAnyAttitudeEndsWithNull) {
    EXPECT_TRUE(send(R"({"id":1,"method":"center","params":{"wait":true}})").empty());
    EXPECT_EQ(api_.calls.back(), "center wait by 7");
    api_.end_waiter({daemon::EndReason::kTimeout, std::nullopt, daemon::Millis(10000)});
    ASSERT_EQ(replies_.size(), 1u);
    EXPECT_EQ(replies_[0]["result"]["sent"], true);
    EXPECT_EQ(replies_[0]["result"]["ended"]["reason"], "timeout");
    EXPECT_TRUE(replies_[0]["result"]["ended"]["attitude"].is_null());
}

TEST_F(WaitDispatcherTest, WithoutWaitNothingWaits) {
    auto replies = send(R"({"id":1,"method":"angle","params":{"pitch":10,"wait":false}})");
    ASSERT_EQ(replies.size(), 1u);
    EXPECT_FALSE(replies[0]["result"].contains("ended"));
    EXPECT_EQ(send(R"({"id":2,"method":"center"})")[0]["result"],
              json::parse(R"({"sent":true,"target":{"roll":0,"pitch":0,"yaw":0},"clamped":[]})"));
    EXPECT_TRUE(api_.waiters.empty());
}

TEST_F(WaitDispatcherTest, OtherRequestsAreServedWhileOneWaits) {
    EXPECT_TRUE(send(R"({"id":1,"method":"angle","params":{"yaw":10,"wait":true}})").empty());
    auto status = send(R"({"id":2,"method":"status"})");
    ASSERT_EQ(status.size(), 1u);
    EXPECT_EQ(status[0]["id"], 2);
    api_.end_waiter({daemon::EndReason::kStop, std::nullopt, daemon::Millis(5)});
    ASSERT_EQ(replies_.size(), 2u);
    EXPECT_EQ(replies_[1]["id"], 1);
    EXPECT_EQ(replies_[1]["result"]["ended"]["reason"], "stop");
}

TEST_F(WaitDispatcherTest, ABatchWithAWaiterAnswersWhenTheMotionEnds) {
    EXPECT_TRUE(send(R"([{"id":1,"method":"center","params":{"wait":true}},)"
                     R"({"id":2,"method":"photo"}])")
                    .empty());
    api_.end_waiter({daemon::EndReason::kReplaced, std::nullopt, daemon::Millis(5)});
    ASSERT_EQ(replies_.size(), 1u);
    ASSERT_TRUE(replies_[0].is_array());
    EXPECT_EQ(replies_[0][0]["result"]["ended"]["reason"], "replaced");
    EXPECT_EQ(replies_[0][1]["result"]["sent"], true);
}

TEST_F(WaitDispatcherTest, StatusShowsATrackedMotionWithItsTarget) {
    daemon::MotionStatus motion;
    motion.mode = daemon::MotionMode::kAngle;
    motion.owner = client_.info;
    motion.target = {0, -4550, 1000};
    motion.elapsed = daemon::Millis(250);
    api_.status_value.motion = motion;
    auto result = send(R"({"id":1,"method":"status"})")[0]["result"]["motion"];
    EXPECT_EQ(result, json({{"mode", "angle"},
                            {"owner", {{"id", 7}, {"pid", 4242}, {"uid", 1000}, {"gid", 1000}}},
                            {"target", {{"roll", 0.0}, {"pitch", -45.5}, {"yaw", 10.0}}},
                            {"elapsed_ms", 250}}));
}

// ---- over the socket ------------------------------------------------------------

TEST(WaitServer, AClientClosingWhileItWaitsIsSafe) {
    ServerHarness h;
    {
        TestClient c(h.path());
        c.send(R"({"id":1,"method":"angle","params":{"pitch":10,"wait":true}})"
               "\n");
        ASSERT_TRUE(h.eventually([&] { return h.api.waiters.size() == 1; }));
    }
    // The deadman has run; the session stays until the reply owed is written
    // (the real core ends a waiter's motion in client_gone).
    ASSERT_TRUE(h.eventually([&] { return h.api.gone.size() == 1; }));
    h.on_io([&] {
        h.api.end_waiter(reached_at({0, 1000, 0}));  // its peer is gone
        return 0;
    });
    ASSERT_TRUE(h.eventually([&] { return h.api.closed.size() == 1; }));
    TestClient other(h.path());
    EXPECT_EQ(other.call("stop")["result"]["sent"], true);
}

TEST(WaitServer, AMotionEndingAfterTheServerClosedTheSessionIsSafe) {
    ServerHarness h;
    TestClient c(h.path());
    c.send(R"({"id":1,"method":"angle","params":{"pitch":10,"wait":true}})"
           "\n");
    ASSERT_TRUE(h.eventually([&] { return h.api.waiters.size() == 1; }));
    h.on_io([&] {
        h.server->close();
        h.api.end_waiter(reached_at({0, 1000, 0}));
        return 0;
    });
    EXPECT_TRUE(c.closed_by_server());
}

TEST(WaitServer, AHalfClosedWaiterStillGetsItsReply) {
    ServerHarness h;
    TestClient c(h.path());
    c.send(R"({"id":1,"method":"center","params":{"wait":true}})"
           "\n");
    ASSERT_TRUE(h.eventually([&] { return h.api.waiters.size() == 1; }));
    c.shutdown_write();
    ASSERT_TRUE(h.eventually([&] { return h.api.gone.size() == 1; }));
    h.on_io([&] {
        h.api.end_waiter({daemon::EndReason::kOwnerGone, std::nullopt, daemon::Millis(5)});
        return 0;
    });
    auto reply = c.next();
    EXPECT_EQ(reply["result"]["ended"]["reason"], "owner_gone");
    EXPECT_TRUE(c.closed_by_server()) << "closed once the reply owed is written";
}

TEST(WaitServer, TheSameClientIsServedWhileItWaits) {
    ServerHarness h;
    TestClient c(h.path());
    c.send(R"({"id":100,"method":"angle","params":{"roll":5,"wait":true}})"
           "\n");
    EXPECT_EQ(c.call("photo")["result"]["sent"], true);
    EXPECT_EQ(c.call("status")["result"]["clients"], 1);
    h.on_io([&] {
        h.api.end_waiter(reached_at({500, 0, 0}));
        return 0;
    });
    auto reply = c.next();
    EXPECT_EQ(reply["id"], 100);
    EXPECT_EQ(reply["result"]["ended"]["reason"], "reached");
    EXPECT_EQ(reply["result"]["ended"]["attitude"]["hall"]["roll"], 5.0);
}

}  // namespace
}  // namespace gport::ipc
