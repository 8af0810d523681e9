// The attitude_channel method over the real socket: the descriptor comes
// with the reply, the ring holds every sample, status counts the readers,
// and closing the server closes the ring and wakes its waiters.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <atomic>
#include <thread>

#include "channel_client.hpp"
#include "gport/base/futex.hpp"
#include "server_harness.hpp"

namespace gport::ipc {
namespace {

using nlohmann::json;
using testing::DescriptorClient;
using testing::RingMapping;
using testing::ServerHarness;

daemon::AttitudeSample channel_sample(std::uint64_t seq, bool rates) {
    daemon::AttitudeSample s;
    s.seq = seq;
    s.wall = daemon::WallTime(std::chrono::microseconds(1'763'770'000'123'456LL));
    s.received = std::chrono::steady_clock::now();
    s.attitude.imu = {-1921, 250, static_cast<std::int16_t>(seq)};
    s.attitude.hall = {1, -3929, 18000};
    if (rates) {
        s.attitude.rates = protocol::AttitudeRates{{125, -5, 0}, 12, -230, 0};
    }
    return s;
}

void publish_samples(ServerHarness& h, std::uint64_t first, std::uint64_t count,
                     bool rates = false) {
    h.on_io([&] {
        for (auto seq = first; seq < first + count; ++seq) {
            h.api.observer->on_attitude(channel_sample(seq, rates));
        }
    });
}

TEST(AttitudeChannel, TheReplyCarriesOneDescriptorOfTheDescribedBlock) {
    ServerHarness h;
    DescriptorClient client(h.path());
    const auto reply = client.call("attitude_channel");
    ASSERT_TRUE(reply.contains("result")) << reply;
    EXPECT_EQ(
        reply["result"],
        (json{{"version", 1}, {"slots", 64}, {"size", base::ring_bytes(64)}, {"published", 0}}));
    ASSERT_EQ(client.descriptors(), 1u);
    const int fd = client.take_descriptor();
    struct stat info {};
    ASSERT_EQ(::fstat(fd, &info), 0);
    EXPECT_EQ(static_cast<std::size_t>(info.st_size), base::ring_bytes(64));
    RingMapping ring(fd, base::ring_bytes(64));
    ::close(fd);
    ASSERT_TRUE(ring.mapped());
    EXPECT_EQ(ring.check(), std::nullopt);
    EXPECT_EQ(ring.reader().published(), 0u);
    EXPECT_FALSE(ring.reader().closed());
}

TEST(AttitudeChannel, EverySampleIsInTheRingWithTheNotificationsValues) {
    ServerHarness h;
    publish_samples(h, 1, 5);  // before anyone asked: no block yet, nothing kept
    DescriptorClient client(h.path());
    ASSERT_EQ(client.call("attitude_channel")["result"]["published"], 0);
    RingMapping ring(client.take_descriptor(), base::ring_bytes(64));
    publish_samples(h, 6, 3);
    publish_samples(h, 9, 1, true);
    const auto reader = ring.reader();
    ASSERT_EQ(reader.published(), 4u);
    for (std::uint64_t n = 1; n <= 3; ++n) {
        auto s = reader.read(n);
        ASSERT_TRUE(s);
        EXPECT_EQ(s->seq, n + 5);
        EXPECT_DOUBLE_EQ(s->t, 1763770000.123456);
        EXPECT_EQ(s->imu, (std::array<double, 3>{-19.21, 2.5, static_cast<double>(n + 5) / 100}));
        EXPECT_EQ(s->hall, (std::array<double, 3>{0.01, -39.29, 180}));
        EXPECT_FALSE(s->has_rates);
    }
    auto last = reader.read(4);
    ASSERT_TRUE(last);
    EXPECT_TRUE(last->has_rates);
    EXPECT_EQ(last->hall_rates, (std::array<double, 3>{1.25, -0.05, 0}));
    EXPECT_EQ(last->imu_rates, (std::array<double, 3>{0.12, -2.3, 0}));
    EXPECT_EQ(client.call("attitude_channel")["result"]["published"], 4);
}

TEST(AttitudeChannel, ParamsOtherThanNoneAreRefusedWithoutADescriptor) {
    ServerHarness h;
    DescriptorClient client(h.path());
    EXPECT_TRUE(client.call("attitude_channel", json::object()).contains("result"));
    const auto reply = client.call("attitude_channel", {{"slots", 128}});
    EXPECT_EQ(reply["error"]["code"], -32602);
    EXPECT_NE(reply["error"]["message"].get<std::string>().find("slots"), std::string::npos);
    EXPECT_EQ(client.descriptors(), 1u);  // only the first call's
}

TEST(AttitudeChannel, ABatchCarriesOneDescriptorPerResult) {
    ServerHarness h;
    DescriptorClient client(h.path());
    client.send(R"([{"id":1,"method":"attitude_channel"},{"id":2,"method":"status"},)"
                R"({"id":3,"method":"attitude_channel"}])"
                "\n");
    const auto replies = client.next();
    ASSERT_TRUE(replies && replies->is_array());
    EXPECT_EQ(replies->size(), 3u);
    EXPECT_EQ(client.descriptors(), 2u);
}

TEST(AttitudeChannel, StatusCountsConnectedClientsThatOpenedIt) {
    ServerHarness h;
    DescriptorClient watcher(h.path());
    auto status = watcher.call("status")["result"];
    EXPECT_EQ(status["client"]["attitude_channel"], false);
    EXPECT_EQ(status["attitude_channel_clients"], 0);
    {
        DescriptorClient reader(h.path());
        reader.call("attitude_channel");
        reader.call("attitude_channel");  // counted once
        status = reader.call("status")["result"];
        EXPECT_EQ(status["client"]["attitude_channel"], true);
        EXPECT_EQ(status["attitude_channel_clients"], 1);
        EXPECT_EQ(watcher.call("status")["result"]["client"]["attitude_channel"], false);
    }
    EXPECT_TRUE(h.eventually([&] { return h.server->attitude_channel_clients() == 0; }));
    EXPECT_EQ(watcher.call("status")["result"]["attitude_channel_clients"], 0);
}

// A client that reads only the ring is listening: the idle timeout leaves it.
TEST(AttitudeChannel, AReaderOfTheChannelIsNotClosedAsIdle) {
    config::SocketConfig config;
    config.idle_timeout = std::chrono::milliseconds(200);
    ServerHarness h(config);
    DescriptorClient idle(h.path());
    DescriptorClient reader(h.path());
    ASSERT_TRUE(reader.call("attitude_channel").contains("result"));
    const auto closed = idle.next(std::chrono::seconds(10));  // the idle client's -32004
    ASSERT_TRUE(closed);
    EXPECT_EQ((*closed)["error"]["code"], -32004);
    std::this_thread::sleep_for(std::chrono::milliseconds(800));  // several timeouts
    EXPECT_TRUE(reader.call("status")["result"].is_object());
}

TEST(AttitudeChannel, ClosingTheServerClosesTheRingAndWakesItsWaiters) {
    ServerHarness h;
    DescriptorClient client(h.path());
    client.call("attitude_channel");
    RingMapping ring(client.take_descriptor(), base::ring_bytes(64));
    const auto reader = ring.reader();
    const auto before = reader.wake_word().load();
    publish_samples(h, 1, 1);
    EXPECT_NE(reader.wake_word().load(), before);  // bumped per sample
    std::atomic<int> waits{0};
    std::thread waiter([&] {
        while (!reader.closed()) {
            const auto seen = reader.wake_word().load();
            if (!reader.closed()) {
                base::futex_wait(reader.wake_word(), seen, std::chrono::seconds(30));
                ++waits;
            }
        }
    });
    while (waits.load() == 0 && !reader.closed()) {
        publish_samples(h, 2, 1);  // until the waiter has been woken once: it is waiting
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    h.stop();
    waiter.join();  // woken by the close (or it saw the flag): it does not hang
    EXPECT_TRUE(reader.closed());
    EXPECT_GE(reader.published(), 1u);
}

}  // namespace
}  // namespace gport::ipc
