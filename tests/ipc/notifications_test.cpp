// Notifications over the socket: subscriptions, rate limits and back-pressure.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "server_harness.hpp"
#include "test_client.hpp"

namespace gport::ipc {
namespace {

using nlohmann::json;
using testing::ServerHarness;
using testing::TestClient;

daemon::AttitudeSample sample(std::uint64_t seq) {
    daemon::AttitudeSample s;
    s.seq = seq;
    s.wall = std::chrono::system_clock::now();
    s.received = std::chrono::steady_clock::now();
    s.attitude.imu = {100, 200, static_cast<std::int16_t>(seq % 30000)};
    return s;
}

void publish(ServerHarness& h, std::uint64_t first, std::uint64_t count) {
    h.on_io([&] {
        for (auto seq = first; seq < first + count; ++seq) {
            h.api.observer->on_attitude(sample(seq));
        }
    });
}

TEST(Notifications, GoOnlyToSubscribersOfTheirTopic) {
    ServerHarness h;
    TestClient all(h.path());
    TestClient links(h.path());
    TestClient none(h.path());
    ASSERT_EQ(
        all.call("subscribe", {{"topics", {"attitude", "link", "motion"}}})["result"]["topics"]
            .size(),
        3u);
    links.call("subscribe", {{"topics", {"link"}}});
    none.call("status");
    publish(h, 1, 1);
    h.on_io([&] { h.api.observer->on_link({daemon::LinkState::kUp, "attitude arriving"}); });
    daemon::MotionEvent motion;
    motion.change = daemon::MotionChange::kEnded;
    motion.reason = daemon::EndReason::kOwnerGone;
    h.on_io([&] { h.api.observer->on_motion(motion); });

    auto a1 = all.next();
    EXPECT_EQ(a1["method"], "attitude");
    EXPECT_EQ(a1["jsonrpc"], "2.0");
    EXPECT_EQ(a1["params"]["imu"]["pitch"], 2.0);
    EXPECT_FALSE(a1.contains("id"));
    EXPECT_EQ(all.next()["params"]["state"], "up");
    EXPECT_EQ(all.next()["params"]["reason"], "owner_gone");
    EXPECT_EQ(links.next()["method"], "link");
    // Nothing was queued for the others before these replies.
    EXPECT_TRUE(links.call("status")["result"].is_object());
    EXPECT_EQ(none.next(std::chrono::milliseconds(200)), json());
    all.call("unsubscribe", {{"topics", {"attitude"}}});
    publish(h, 2, 1);
    h.on_io([&] { h.api.observer->on_link({daemon::LinkState::kStale, "quiet"}); });
    EXPECT_EQ(all.next()["method"], "link");
}

TEST(Notifications, MotionCausedByARequestReachesSubscribers) {
    ServerHarness h;
    h.on_io([&] { h.api.emit_motion = true; });
    TestClient watcher(h.path());
    TestClient mover(h.path());
    watcher.call("subscribe", {{"topics", {"motion"}}});
    EXPECT_EQ(mover.call("speed", {{"yaw", 10}, {"duration_ms", 500}})["result"]["duration_ms"],
              500);
    auto event = watcher.next();
    EXPECT_EQ(event["params"]["change"], "started");
    EXPECT_EQ(event["params"]["speed"]["yaw"], 10.0);
}

TEST(Notifications, RateLimitedSubscriberEndsUpWithTheNewestSample) {
    ServerHarness h;
    TestClient c(h.path());
    c.call("subscribe", {{"topics", {"attitude"}}, {"max_rate_hz", 2}});
    publish(h, 1, 50);
    std::vector<int> seen;
    for (auto line = c.next(std::chrono::seconds(3)); !line.is_null();
         line = c.next(std::chrono::seconds(2))) {
        seen.push_back(line["params"]["seq"].get<int>());
    }
    ASSERT_FALSE(seen.empty());
    EXPECT_LT(seen.size(), 5u) << "at most ~2 per second";
    EXPECT_EQ(seen.front(), 1);
    EXPECT_EQ(seen.back(), 50) << "latest wins: the newest sample is delivered, not dropped";
}

TEST(Notifications, WithoutARateEverySampleArrivesInOrder) {
    ServerHarness h;
    TestClient c(h.path());
    c.call("subscribe", {{"topics", {"attitude"}}});
    publish(h, 1, 200);
    for (int seq = 1; seq <= 200; ++seq) {
        ASSERT_EQ(c.next()["params"]["seq"], seq);
    }
}

// A client that stops reading loses attitude samples (counted, reported) but
// is not disconnected for it, and never delays a client that keeps up.
TEST(Notifications, SlowReaderLosesAttitudeOnlyAndDelaysNobody) {
    config::SocketConfig config;
    config.queue_limit = 16;
    ServerHarness h(config);
    TestClient slow(h.path());
    TestClient fast(h.path());
    slow.call("subscribe", {{"topics", {"attitude"}}});
    fast.call("subscribe", {{"topics", {"attitude"}}});
    // Bursts smaller than the queue: a client that reads keeps up.
    constexpr int kBatches = 1000;
    constexpr int kPerBatch = 10;
    for (int b = 0; b < kBatches; ++b) {
        publish(h, static_cast<std::uint64_t>(b * kPerBatch + 1), kPerBatch);
        for (int i = 1; i <= kPerBatch; ++i) {
            ASSERT_EQ(fast.next()["params"]["seq"], b * kPerBatch + i);
        }
    }
    EXPECT_EQ(h.on_io([&] { return h.server->clients(); }), 2u) << "the slow one stays";
    const auto dropped = h.on_io([&] { return h.server->dropped_notifications(); });
    EXPECT_GT(dropped, 0u);

    // Reading again, it finds a sample that reports its loss, and the newest.
    std::uint64_t reported = 0;
    int last = 0;
    for (auto line = slow.next(); !line.is_null(); line = slow.next(std::chrono::seconds(1))) {
        last = line["params"]["seq"].get<int>();
        if (line["params"].contains("dropped")) {
            reported = line["params"]["dropped"].get<std::uint64_t>();
        }
    }
    EXPECT_GT(reported, 0u);
    EXPECT_EQ(last, kBatches * kPerBatch);
    auto status = slow.call("status")["result"];
    EXPECT_EQ(status["client"]["dropped"].get<std::uint64_t>(), dropped);
    EXPECT_EQ(status["dropped_notifications"].get<std::uint64_t>(), dropped);
}

// A client that sends requests but never reads the replies is disconnected
// once they cannot be queued; the others carry on.
TEST(Notifications, ClientWhoseRepliesCannotBeQueuedIsDisconnected) {
    config::SocketConfig config;
    config.queue_limit = 16;
    ServerHarness h(config);
    TestClient other(h.path());
    TestClient flooder(h.path());
    ASSERT_EQ(flooder.call("status")["result"]["clients"], 2);
    std::string requests;
    for (int i = 0; i < 200; ++i) {
        requests += R"({"id":1,"method":"status"})"
                    "\n";
    }
    for (int i = 0; i < 200 && flooder.send(requests); ++i) {
    }
    EXPECT_TRUE(h.eventually([&] { return h.server->clients() == 1; }));
    EXPECT_TRUE(flooder.closed_by_server());
    EXPECT_EQ(h.on_io([&] { return h.api.gone.size(); }), 1u);
    EXPECT_EQ(other.call("stop")["result"]["sent"], true);
}

}  // namespace
}  // namespace gport::ipc
