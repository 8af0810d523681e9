// The attitude_channel method over the real socket: a connection's first
// reply carries the ring and its own wake block, later ones nothing; the
// ring holds every sample; each reader connection's word wakes one waiter
// per sample and is never touched once it left; status counts the readers
// and the failures, which are logged once, then summarised; closing the
// server closes the ring and wakes its waiters.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include <atomic>
#include <memory>
#include <sstream>
#include <thread>
#include <vector>

#include "channel_helpers.hpp"
#include "gport/base/futex.hpp"

namespace gport::ipc {
namespace {

using nlohmann::json;
using testing::channel_batch;
using testing::channel_result;
using testing::DescriptorClient;
using testing::open_channel;
using testing::publish_samples;
using testing::RingMapping;
using testing::ServerHarness;
using testing::WakeMapping;
using testing::wakes_done;

TEST(AttitudeChannel, TheFirstReplyCarriesTheRingAndAWakeBlockLaterOnesNothing) {
    ServerHarness h;
    DescriptorClient client(h.path());
    const auto reply = client.call("attitude_channel");
    ASSERT_TRUE(reply.contains("result")) << reply;
    EXPECT_EQ(reply["result"], channel_result(0, 2));
    ASSERT_EQ(client.descriptors(), 2u);
    const int ring_fd = client.take_descriptor();
    const int wake_fd = client.take_descriptor();
    struct stat ring_info {};
    struct stat wake_info {};
    ASSERT_EQ(::fstat(ring_fd, &ring_info), 0);
    ASSERT_EQ(::fstat(wake_fd, &wake_info), 0);
    EXPECT_EQ(static_cast<std::size_t>(ring_info.st_size), base::ring_bytes(64));
    EXPECT_EQ(static_cast<std::size_t>(wake_info.st_size), base::kWakeBlockBytes);
    const int seals = F_SEAL_SHRINK | F_SEAL_GROW | F_SEAL_FUTURE_WRITE | F_SEAL_SEAL;
    EXPECT_EQ(::fcntl(ring_fd, F_GET_SEALS), seals);
    EXPECT_EQ(::fcntl(wake_fd, F_GET_SEALS), seals);
    EXPECT_EQ(::mmap(nullptr, 64, PROT_READ | PROT_WRITE, MAP_SHARED, wake_fd, 0), MAP_FAILED);
    EXPECT_EQ(::ftruncate(wake_fd, 0), -1);
    RingMapping ring(ring_fd, base::ring_bytes(64));
    WakeMapping wake(wake_fd);
    ::close(ring_fd);
    ::close(wake_fd);
    ASSERT_TRUE(ring.mapped() && wake.mapped());
    EXPECT_EQ(ring.check(), std::nullopt);
    EXPECT_EQ(wake.check(), std::nullopt);
    EXPECT_EQ(ring.reader().published(), 0u);
    EXPECT_FALSE(ring.reader().closed());
    // Later requests on the same connection: the same answer, no descriptor.
    for (int i = 0; i < 3; ++i) {
        EXPECT_EQ(client.call("attitude_channel")["result"], channel_result(0, 0));
    }
    EXPECT_EQ(client.descriptors(), 0u);
}

// An attacker that asks in batches of 32 and never reads held 32 copies in
// flight per line until gportd's RLIMIT_NOFILE was used up (ETOOMANYREFS
// for everyone). Now a connection has at most its two in flight, once.
TEST(AttitudeChannel, ABatchOf32GetsOneSetOfDescriptors) {
    ServerHarness h;
    DescriptorClient client(h.path());
    const auto batch = channel_batch(32);
    ASSERT_TRUE(client.send(batch + batch));
    std::size_t with_descriptors = 0;
    for (int line = 0; line < 2; ++line) {
        const auto replies = client.next();
        ASSERT_TRUE(replies && replies->is_array() && replies->size() == 32);
        for (const auto& reply : *replies) {
            ASSERT_TRUE(reply.contains("result")) << reply;
            with_descriptors += reply["result"]["descriptors"] == 2 ? 1 : 0;
        }
    }
    EXPECT_EQ(with_descriptors, 1u);
    EXPECT_EQ(client.descriptors(), 2u);
}

TEST(AttitudeChannel, EverySampleIsInTheRingWithTheNotificationsValues) {
    ServerHarness h;
    publish_samples(h, 1, 5);  // before anyone asked: no block yet, nothing kept
    DescriptorClient client(h.path());
    auto opened = open_channel(client);
    auto& ring = *opened.ring;
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
    const auto refused = client.call("attitude_channel", {{"slots", 128}});
    EXPECT_EQ(refused["error"]["code"], -32602);
    EXPECT_NE(refused["error"]["message"].get<std::string>().find("slots"), std::string::npos);
    EXPECT_EQ(client.descriptors(), 0u);
    EXPECT_EQ(client.call("attitude_channel", json::object())["result"]["descriptors"], 2);
    EXPECT_EQ(client.descriptors(), 2u);  // the refusal did not use them up
}

// A notification opens the channel but its reply is never sent: it must
// not use up the connection's descriptors, in a batch or alone.
TEST(AttitudeChannel, ANotificationDoesNotUseUpTheDescriptors) {
    ServerHarness h;
    DescriptorClient client(h.path());
    ASSERT_TRUE(client.send(R"({"jsonrpc":"2.0","method":"attitude_channel"})"
                            "\n"
                            R"([{"jsonrpc":"2.0","method":"attitude_channel"},)"
                            R"({"jsonrpc":"2.0","id":7,"method":"status"}])"
                            "\n"));
    const auto batch = client.next();
    ASSERT_TRUE(batch && batch->is_array() && batch->size() == 1);
    EXPECT_EQ((*batch)[0]["result"]["client"]["attitude_channel"], true);
    EXPECT_EQ(client.descriptors(), 0u);
    EXPECT_EQ(client.call("attitude_channel")["result"]["descriptors"], 2);
    EXPECT_EQ(client.descriptors(), 2u);
}

// gportd's cost per sample is one FUTEX_WAKE(1) per reader connection,
// however many threads wait on its word: 50 threads parked on one
// connection's word, one sample, exactly one of them woken.
TEST(AttitudeChannel, ASampleWakesOneWaiterPerConnectionHoweverManyWait) {
    ServerHarness h;
    DescriptorClient client(h.path());
    auto opened = open_channel(client);
    const auto& word = opened.wake->word();
    std::atomic<int> parked{0};
    std::atomic<int> woken{0};
    std::atomic<bool> done{false};
    std::vector<std::thread> threads;
    const auto seen = word.load();
    for (int i = 0; i < 50; ++i) {
        threads.emplace_back([&] {
            ++parked;
            while (!done) {
                if (base::futex_wait(word, seen, std::chrono::seconds(30)) ==
                    base::FutexWait::kWoken) {
                    ++woken;
                    return;
                }
                if (word.load() != seen) {
                    return;  // not parked in time: it saw the change instead
                }
            }
        });
    }
    while (parked.load() < 50) {
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));  // all in FUTEX_WAIT
    publish_samples(h, 1, 1);
    EXPECT_TRUE(h.eventually([&] { return woken.load() >= 1; }));
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    EXPECT_EQ(woken.load(), 1);
    EXPECT_EQ(word.load(), seen + 1);  // bumped once
    done = true;
    base::futex_wake_all(word);  // the test's own threads: a read-only mapping can wake
    for (auto& t : threads) {
        t.join();
    }
}

// Each connection has its own word: one parked on by an attacker is not the
// one another reader sleeps on, and a connection that left is never bumped.
TEST(AttitudeChannel, EachConnectionHasItsOwnWordAndOneThatLeftIsNeverBumped) {
    ServerHarness h;
    auto gone = std::make_unique<DescriptorClient>(h.path());
    auto gone_channel = open_channel(*gone);
    DescriptorClient stays(h.path());
    auto stays_channel = open_channel(stays);
    publish_samples(h, 1, 2);
    ASSERT_TRUE(wakes_done(h));
    // Bumped at least once (two samples may share a round of the waker).
    EXPECT_GE(gone_channel.wake->word().load(), 1u);
    EXPECT_GE(stays_channel.wake->word().load(), 1u);
    gone.reset();  // disconnects; its mapping is ours still
    EXPECT_TRUE(h.eventually([&] { return h.server->attitude_channel_clients() == 1; }));
    const auto gone_word = gone_channel.wake->word().load();
    const auto stays_word = stays_channel.wake->word().load();
    publish_samples(h, 3, 5);
    ASSERT_TRUE(wakes_done(h));
    EXPECT_EQ(gone_channel.wake->word().load(), gone_word);  // untouched
    EXPECT_GT(stays_channel.wake->word().load(), stays_word);
    EXPECT_EQ(gone_channel.ring->reader().published(), 7u);  // the ring is shared
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
    auto opened = open_channel(client);
    const auto reader = opened.ring->reader();
    const auto& word = opened.wake->word();
    const auto before = word.load();
    publish_samples(h, 1, 1);
    ASSERT_TRUE(wakes_done(h));
    EXPECT_NE(word.load(), before);  // bumped per sample
    std::atomic<int> waits{0};
    std::thread waiter([&] {
        while (!reader.closed()) {
            const auto seen = word.load();
            if (!reader.closed()) {
                base::futex_wait(word, seen, std::chrono::seconds(30));
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

// Out of descriptors: each request gets -32603 naming the cause, status
// counts them, the log has one line (then summaries), and the next request
// after the shortage gets the descriptors.
TEST(AttitudeChannel, ExhaustionIsRefusedCountedAndLoggedOnce) {
    std::ostringstream out;
    auto log = std::make_shared<spdlog::logger>(
        "test", std::make_shared<spdlog::sinks::ostream_sink_mt>(out));
    ServerHarness h({}, log);
    DescriptorClient first(h.path());
    open_channel(first);  // the ring exists; each further reader needs a wake block
    std::vector<std::unique_ptr<DescriptorClient>> readers;
    for (int i = 0; i < 4; ++i) {
        readers.push_back(std::make_unique<DescriptorClient>(h.path()));
    }
    EXPECT_TRUE(h.eventually([&] { return h.server->clients() == 5; }));
    rlimit saved{};
    ASSERT_EQ(::getrlimit(RLIMIT_NOFILE, &saved), 0);
    const int lowest_free = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
    ::close(lowest_free);
    rlimit low = saved;
    low.rlim_cur = static_cast<rlim_t>(lowest_free);  // no new descriptor fits
    ASSERT_EQ(::setrlimit(RLIMIT_NOFILE, &low), 0);
    std::vector<json> replies;
    for (auto& reader : readers) {
        replies.push_back(reader->call("attitude_channel"));
    }
    ASSERT_EQ(::setrlimit(RLIMIT_NOFILE, &saved), 0);
    for (const auto& reply : replies) {
        ASSERT_TRUE(reply.contains("error")) << reply;
        EXPECT_EQ(reply["error"]["code"], -32603);
        EXPECT_NE(reply["error"]["message"].get<std::string>().find(
                      "attitude channel unavailable: memfd_create (wake block): Too many open "
                      "files"),
                  std::string::npos)
            << reply;
    }
    EXPECT_EQ(first.call("status")["result"]["attitude_channel_failures"], 4);
    const auto again = readers[0]->call("attitude_channel");
    EXPECT_EQ(again["result"]["descriptors"], 2) << again;
    EXPECT_EQ(readers[0]->descriptors(), 2u);
    const auto text = out.str();
    std::size_t lines = 0;
    for (auto at = text.find("attitude channel unavailable"); at != std::string::npos;
         at = text.find("attitude channel unavailable", at + 1)) {
        ++lines;
    }
    EXPECT_EQ(lines, 1u) << text;
    EXPECT_NE(text.find("1 time(s) since the last report"), std::string::npos) << text;
}

}  // namespace
}  // namespace gport::ipc
