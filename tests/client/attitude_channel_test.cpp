// The shared-memory attitude channel in libgport-client against a fake
// gportd (fake_server.hpp): a connection's two blocks shared by its later
// requests, the checks of the blocks, next/latest/missed/closed, waking one
// waiter per connection and passing it on, and the transparent subscription
// of Client and AsyncClient. A hostile server: channel_attacks_test.cpp.
// The real daemon: attitude_channel_e2e_test.cpp.
#include "gport/client/attitude_channel.hpp"

#include <gtest/gtest.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <thread>
#include <variant>
#include <vector>

#include "fake_server.hpp"
#include "gport/client/async_client.hpp"
#include "gport/client/client.hpp"

namespace gport::testing {
namespace {

namespace gc = gport::client;
using namespace std::chrono_literals;

TEST(AttitudeChannel, FirstNextGivesTheNewestThenEachSampleInOrder) {
    FakeServer server;
    RingBlock block;
    server.offer(&block);
    auto client = gc::Client::connect(server.path());
    auto channel = client.attitude_channel();
    EXPECT_FALSE(channel.latest());
    EXPECT_FALSE(channel.next(0ms));
    block.publish(1);
    block.publish(2, true);
    auto first = channel.next(1s);
    ASSERT_TRUE(first);
    EXPECT_EQ(first->seq, 2U);
    ASSERT_TRUE(first->rates);
    EXPECT_DOUBLE_EQ(first->rates->hall.pitch, 2);
    EXPECT_DOUBLE_EQ(first->rates->imu.z, 6);
    EXPECT_DOUBLE_EQ(first->imu.roll, 0.2);
    EXPECT_DOUBLE_EQ(first->hall.yaw, 44.75);
    EXPECT_FALSE(first->age_ms);
    block.publish(3);
    block.publish(4);
    EXPECT_EQ(channel.next(1s)->seq, 3U);
    EXPECT_EQ(channel.next(1s)->seq, 4U);
    EXPECT_FALSE(channel.next(20ms));
    EXPECT_EQ(channel.latest()->seq, 4U);
    EXPECT_FALSE(channel.latest()->rates);
    EXPECT_EQ(channel.missed(), 0U);
    EXPECT_FALSE(channel.closed());
}

TEST(AttitudeChannel, NextWakesForASamplePublishedWhileItWaits) {
    FakeServer server;
    RingBlock block;
    server.offer(&block);
    auto client = gc::Client::connect(server.path());
    auto channel = client.attitude_channel();
    std::thread writer([&] {
        std::this_thread::sleep_for(50ms);
        block.publish(7);
    });
    const auto sample = channel.next(10s);
    writer.join();
    ASSERT_TRUE(sample);
    EXPECT_EQ(sample->seq, 7U);
}

TEST(AttitudeChannel, AReaderMoreThanARingBehindSkipsAndCountsWhatItMissed) {
    FakeServer server;
    RingBlock block;
    server.offer(&block);
    auto client = gc::Client::connect(server.path());
    auto channel = client.attitude_channel();
    block.publish(1);
    ASSERT_EQ(channel.next(1s)->seq, 1U);
    for (std::uint64_t seq = 2; seq <= 201; ++seq) {
        block.publish(seq);
    }
    const auto sample = channel.next(1s);
    ASSERT_TRUE(sample);
    EXPECT_EQ(sample->seq, 201U - 32);  // half a ring behind the newest
    EXPECT_EQ(channel.missed(), 167U);  // 2 .. 168
    EXPECT_EQ(sample->dropped, 167U);
    EXPECT_EQ(channel.next(1s)->seq, 201U - 31);
}

TEST(AttitudeChannel, ClosedOnceTheWriterStopsAndEverySampleWasTaken) {
    FakeServer server;
    RingBlock block;
    server.offer(&block);
    auto client = gc::Client::connect(server.path());
    auto channel = client.attitude_channel();
    block.publish(1);
    ASSERT_TRUE(channel.next(1s));
    block.publish(2);
    block.close();
    EXPECT_TRUE(channel.closed());
    EXPECT_EQ(channel.next(1s)->seq, 2U);
    const auto start = std::chrono::steady_clock::now();
    EXPECT_FALSE(channel.next(30s));  // returns at once: nothing more will come
    EXPECT_LT(std::chrono::steady_clock::now() - start, 20s);
}

TEST(AttitudeChannel, OutlivesItsClientAndIsMovable) {
    FakeServer server;
    RingBlock block;
    server.offer(&block);
    gc::AttitudeChannel moved;
    EXPECT_TRUE(moved.closed());
    EXPECT_FALSE(moved.next(0ms));
    {
        auto client = gc::Client::connect(server.path());
        moved = client.attitude_channel();
    }
    block.publish(5);
    EXPECT_EQ(moved.next(1s)->seq, 5U);
}

int error_code(const std::function<void()>& f, std::string& message) {
    try {
        f();
    } catch (const gc::Error& e) {
        message = e.message();
        return e.code();
    }
    return 0;
}

TEST(AttitudeChannel, ABlockThatFailsItsChecksIsAnErrorNamingTheProblem) {
    FakeServer server;
    RingBlock bad_magic;
    bad_magic.corrupt_magic();
    RingBlock bad_version;
    bad_version.set_version(9);
    server.offer(&bad_magic);
    server.offer(&bad_version);
    const auto before = open_descriptors();
    auto client = gc::Client::connect(server.path());
    std::string message;
    EXPECT_EQ(error_code([&] { client.attitude_channel(); }, message),
              static_cast<int>(gc::ErrorCode::kBadReply));
    EXPECT_NE(message.find("bad magic"), std::string::npos) << message;
    EXPECT_EQ(error_code([&] { client.attitude_channel(); }, message),
              static_cast<int>(gc::ErrorCode::kBadReply));
    EXPECT_NE(message.find("version 9 is not supported"), std::string::npos) << message;
    client.close();
    for (int i = 0; i < 200 && open_descriptors() != before; ++i) {
        std::this_thread::sleep_for(10ms);  // the fake server closes its side
    }
    EXPECT_EQ(open_descriptors(), before);  // the refused blocks' descriptors were closed
}

TEST(AttitudeChannel, AReplyWithoutItsDescriptorsIsAnError) {
    FakeServer server;
    server.offer(nullptr);
    auto client = gc::Client::connect(server.path());
    std::string message;
    EXPECT_EQ(error_code([&] { client.attitude_channel(); }, message),
              static_cast<int>(gc::ErrorCode::kBadReply));
    EXPECT_NE(message.find("carried 0 file descriptor(s), not the 2 it announced"),
              std::string::npos)
        << message;
}

TEST(AttitudeChannel, LaterRequestsShareTheConnectionsMappingEachWithItsOwnCursor) {
    FakeServer server;
    RingBlock block;
    RingBlock stray;
    server.offer(&block);
    const auto before = open_descriptors();
    {
        auto client = gc::Client::connect(server.path());
        auto first = client.attitude_channel();
        block.publish(1);
        auto second = client.attitude_channel();  // "descriptors":0
        EXPECT_EQ(first.next(1s)->seq, 1U);
        EXPECT_EQ(second.next(1s)->seq, 1U);
        block.publish(2);
        EXPECT_EQ(first.next(1s)->seq, 2U);
        first = gc::AttitudeChannel();
        EXPECT_EQ(second.next(1s)->seq, 2U);  // still mapped
        // Descriptors nobody asked for (on a notification line) are closed at once.
        const auto connected = open_descriptors();
        server.push({{"jsonrpc", "2.0"}, {"method", "link"}, {"params", {{"state", "up"}}}},
                    {stray.fd(), stray.wake_fd()});
        const auto n = client.next_notification(5s);
        ASSERT_TRUE(n);
        EXPECT_TRUE(std::holds_alternative<gc::LinkEvent>(*n));
        EXPECT_EQ(open_descriptors(), connected);
    }
    for (int i = 0; i < 200 && open_descriptors() != before; ++i) {
        std::this_thread::sleep_for(10ms);  // the fake server closes its side
    }
    EXPECT_EQ(open_descriptors(), before);
}

TEST(AttitudeChannel, TransparentSubscriptionDeliversRingSamplesAndSocketNotifications) {
    FakeServer server;
    RingBlock block;
    block.publish(1);  // published before subscribing: not delivered
    server.offer(&block);
    auto client = gc::Client::connect(server.path());
    const auto result =
        client.subscribe({"attitude", "link"}, gc::SubscribeOptions{std::nullopt, true});
    EXPECT_EQ(server.last_subscribe(), nlohmann::json({"link"}));
    EXPECT_EQ(result.topics, (std::vector<std::string>{"link", "attitude"}));
    EXPECT_FALSE(client.next_notification(50ms));
    block.publish(2);
    auto n = client.next_notification(5s);
    ASSERT_TRUE(n);
    ASSERT_TRUE(std::holds_alternative<gc::AttitudeSample>(*n));
    EXPECT_EQ(std::get<gc::AttitudeSample>(*n).seq, 2U);
    server.push({{"jsonrpc", "2.0"}, {"method", "link"}, {"params", {{"state", "stale"}}}});
    n = client.next_notification(5s);
    ASSERT_TRUE(n);
    ASSERT_TRUE(std::holds_alternative<gc::LinkEvent>(*n));
    EXPECT_EQ(std::get<gc::LinkEvent>(*n).state, "stale");
    // With a callback, ring samples reach it from dispatch() and from calls.
    std::vector<std::uint64_t> seen;
    client.on_notification([&](const gc::Notification& m) {
        if (const auto* a = std::get_if<gc::AttitudeSample>(&m)) {
            seen.push_back(a->seq);
        }
    });
    block.publish(3);
    block.publish(4);
    for (int i = 0; i < 100 && seen.size() < 2; ++i) {
        client.dispatch(50ms);
    }
    EXPECT_EQ(seen, (std::vector<std::uint64_t>{3, 4}));
    block.publish(5);
    client.subscribe({"motion"});  // any call
    EXPECT_EQ(seen, (std::vector<std::uint64_t>{3, 4, 5}));
    client.unsubscribe({"attitude"});
    seen.clear();
    block.publish(6);
    client.dispatch(100ms);
    EXPECT_TRUE(seen.empty());
}

TEST(AttitudeChannel, SubscribingOnlyAttitudeSendsNoSocketSubscription) {
    FakeServer server;
    RingBlock block;
    server.offer(&block);
    auto client = gc::Client::connect(server.path());
    const auto result = client.subscribe({"attitude"}, gc::SubscribeOptions{10.0, true});
    EXPECT_EQ(result.topics, std::vector<std::string>{"attitude"});
    EXPECT_TRUE(server.last_subscribe().is_null());
    block.publish(1);
    const auto n = client.next_notification(5s);
    ASSERT_TRUE(n);
    EXPECT_EQ(std::get<gc::AttitudeSample>(*n).seq, 1U);
}

TEST(AttitudeChannel, AClosedConnectionEndsTheTransparentDelivery) {
    FakeServer server;
    RingBlock block;
    server.offer(&block);
    const auto before = open_descriptors();
    {
        auto client = gc::Client::connect(server.path());
        client.subscribe({"attitude"}, gc::SubscribeOptions{std::nullopt, true});
        server.drop();
        std::string message;
        EXPECT_EQ(error_code(
                      [&] {
                          while (true) {
                              client.next_notification(5s);
                          }
                      },
                      message),
                  static_cast<int>(gc::ErrorCode::kTransport));
        EXPECT_FALSE(client.connected());
    }
    for (int i = 0; i < 200 && open_descriptors() != before; ++i) {
        std::this_thread::sleep_for(10ms);  // the fake server closes its side
    }
    EXPECT_EQ(open_descriptors(), before);
}

// gportd wakes ONE waiter per connection and sample; the first thread of
// the process to see the word change wakes the others.
TEST(AttitudeChannel, OneWakePerConnectionReachesEveryWaitingThreadOfTheProcess) {
    FakeServer server;
    RingBlock block;
    block.wakes = 1;  // as gportd
    server.offer(&block);
    auto client = gc::Client::connect(server.path());
    std::vector<gc::AttitudeChannel> channels;
    for (int i = 0; i < 4; ++i) {
        channels.push_back(client.attitude_channel());
    }
    std::vector<std::uint64_t> got(channels.size(), 0);
    std::vector<std::thread> readers;
    for (std::size_t i = 0; i < channels.size(); ++i) {
        readers.emplace_back([&, i] {
            auto sample = channels[i].next(5s);
            got[i] = sample ? sample->seq : 0;
        });
    }
    std::this_thread::sleep_for(300ms);  // all four in FUTEX_WAIT
    const auto start = std::chrono::steady_clock::now();
    block.publish(9);
    for (auto& reader : readers) {
        reader.join();
    }
    EXPECT_EQ(got, (std::vector<std::uint64_t>{9, 9, 9, 9}));
    EXPECT_LT(std::chrono::steady_clock::now() - start, 4s);  // not the 5 s timeout
}

TEST(AttitudeChannel, AsyncClientOpensTheChannelAndSubscribesTransparently) {
    FakeServer server;
    RingBlock first;
    first.publish(41);
    server.offer(&first);
    boost::asio::io_context io;
    gc::AsyncClient client(io);
    boost::asio::steady_timer guard(io, 10s);
    guard.async_wait([&](auto) { client.close(); });
    std::optional<gc::AttitudeChannel> channel;
    std::uint64_t latest = 0;
    std::vector<std::uint64_t> seen;
    std::vector<std::string> topics;
    client.on_notification([&](const gc::Notification& n) {
        if (const auto* a = std::get_if<gc::AttitudeSample>(&n)) {
            seen.push_back(a->seq);
            if (seen.size() == 2) {
                client.close();
                guard.cancel();
            }
        }
    });
    client.async_connect(server.path(), [&](std::optional<gc::Error> error) {
        ASSERT_FALSE(error);
        client.async_attitude_channel([&](std::optional<gc::Error> e, gc::AttitudeChannel c) {
            ASSERT_FALSE(e) << e->what();
            channel = std::move(c);
            latest = channel->latest()->seq;
            client.async_subscribe({"attitude", "motion"}, gc::SubscribeOptions{std::nullopt, true},
                                   [&](std::optional<gc::Error> e2, gc::Subscription s) {
                                       ASSERT_FALSE(e2) << e2->what();
                                       topics = s.topics;
                                       std::thread([&] {
                                           first.publish(1);
                                           first.publish(2);
                                       }).detach();
                                   });
        });
    });
    std::thread runner([&] { io.run_for(15s); });
    runner.join();
    ASSERT_TRUE(channel);
    EXPECT_EQ(latest, 41U);
    EXPECT_EQ(topics, (std::vector<std::string>{"motion", "attitude"}));
    EXPECT_EQ(server.last_subscribe(), nlohmann::json({"motion"}));
    EXPECT_EQ(seen, (std::vector<std::uint64_t>{1, 2}));
}

TEST(AttitudeChannel, AsyncClientRejectsABadBlock) {
    FakeServer server;
    RingBlock bad;
    bad.corrupt_magic();
    server.offer(&bad);
    boost::asio::io_context io;
    gc::AsyncClient client(io);
    std::optional<gc::Error> error;
    client.async_connect(server.path(), [&](std::optional<gc::Error> e) {
        ASSERT_FALSE(e);
        client.async_attitude_channel([&](std::optional<gc::Error> e2, gc::AttitudeChannel c) {
            error = e2;
            EXPECT_TRUE(c.closed());
            client.close();
        });
    });
    io.run_for(10s);
    ASSERT_TRUE(error);
    EXPECT_TRUE(error->is(gc::ErrorCode::kBadReply));
    EXPECT_NE(error->message().find("bad magic"), std::string::npos);
}

}  // namespace
}  // namespace gport::testing
