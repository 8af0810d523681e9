// A hostile gportd against libgport-client's shared-memory channel (issue
// 22, items 6 and 8), each attack performed by the fake server: blocks
// without seals, truncated or of the wrong size, a slot count rewritten
// after the check, more descriptors than announced, "descriptors":0 on a
// connection without a channel, descriptors attached to notifications, and
// late replies to timed-out attitude_channel calls.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#include <bit>
#include <boost/asio/io_context.hpp>
#include <chrono>
#include <functional>
#include <string>

#include "fake_server.hpp"
#include "gport/client/async_client.hpp"
#include "gport/client/client.hpp"
#include "gport/client/ring_read.h"

namespace gport::testing {
namespace {

namespace gc = gport::client;
using namespace std::chrono_literals;

// The message of the kBadReply error `f` throws ("" if none).
std::string bad_reply(const std::function<void()>& f) {
    try {
        f();
    } catch (const gc::Error& e) {
        EXPECT_TRUE(e.is(gc::ErrorCode::kBadReply)) << e.message();
        return e.message();
    }
    ADD_FAILURE() << "no error";
    return {};
}

std::size_t settled(std::size_t before) {
    for (int i = 0; i < 200 && open_descriptors() != before; ++i) {
        std::this_thread::sleep_for(10ms);  // the fake server closes its side
    }
    return open_descriptors();
}

TEST(ChannelAttacks, ABlockWithoutSealsIsRefused) {
    FakeServer server;
    RingBlock unsealed(64, 0);
    server.offer(&unsealed);
    const auto before = open_descriptors();
    {
        auto client = gc::Client::connect(server.path());
        const auto message = bad_reply([&] { client.attitude_channel(); });
        EXPECT_NE(message.find("the ring is not sealed against shrinking and writing (seals 0x0"),
                  std::string::npos)
            << message;
        EXPECT_TRUE(client.connected());
    }
    EXPECT_EQ(settled(before), before);
}

// Before: the client mapped what the reply announced and read past the end
// of a shorter file: SIGBUS. Now fstat says so before anything is mapped.
TEST(ChannelAttacks, ATruncatedBlockIsRefusedBeforeItIsMapped) {
    FakeServer server;
    RingBlock truncated(64, 0);
    ASSERT_EQ(::ftruncate(truncated.fd(), 4096), 0);
    ASSERT_EQ(::fcntl(truncated.fd(), F_ADD_SEALS, kSeals), 0);
    server.offer(Offer{&truncated, std::nullopt, {{"size", base::ring_bytes(64)}}});
    auto client = gc::Client::connect(server.path());
    const auto message = bad_reply([&] { client.attitude_channel(); });
    EXPECT_NE(message.find("the ring is 4096 bytes, not the 8256 expected"), std::string::npos)
        << message;
}

// The seals come first: a block that may still shrink is refused before
// its size is looked at, since a server holding another descriptor could
// shrink it after that look and seal it then (before: the size was looked
// at first, so this block was refused for its size, and one truncated in
// between the two looks was mapped at the old size: SIGBUS).
TEST(ChannelAttacks, ABlockThatMayShrinkIsRefusedBeforeItsSizeIsLookedAt) {
    FakeServer server;
    RingBlock shrinkable(64, 0);
    ASSERT_EQ(::ftruncate(shrinkable.fd(), 4096), 0);
    ASSERT_EQ(::fcntl(shrinkable.fd(), F_ADD_SEALS, kSeals & ~unsigned{F_SEAL_SHRINK}), 0);
    server.offer(Offer{&shrinkable, std::nullopt, {{"size", base::ring_bytes(64)}}});
    auto client = gc::Client::connect(server.path());
    const auto message = bad_reply([&] { client.attitude_channel(); });
    EXPECT_NE(message.find("the ring is not sealed against shrinking and writing (seals 0x15;"),
              std::string::npos)
        << message;
}

TEST(ChannelAttacks, AReplyWhoseSizeDoesNotFitItsSlotsIsRefused) {
    FakeServer server;
    RingBlock block;
    server.offer(Offer{&block, std::nullopt, {{"size", 1 << 30}}});
    server.offer(Offer{&block, std::nullopt, {{"slots", 6}}});
    server.offer(Offer{&block, std::nullopt, {{"version", 1}}});
    server.offer(Offer{&block, std::nullopt, {{"descriptors", 5}}});
    auto client = gc::Client::connect(server.path());
    EXPECT_NE(bad_reply([&] {
                  client.attitude_channel();
              }).find("size = 1073741824 does not fit 64 slots"),
              std::string::npos);
    EXPECT_NE(bad_reply([&] {
                  client.attitude_channel();
              }).find("slots = 6 is not a power of two from 1 to 65536"),
              std::string::npos);
    EXPECT_NE(bad_reply([&] { client.attitude_channel(); })
                  .find("gportd's channel is version 1; this library reads version 2 (update "
                        "gportd)"),
              std::string::npos);
    EXPECT_NE(
        bad_reply([&] { client.attitude_channel(); }).find("descriptors = 5; gportd sends 2 or 0"),
        std::string::npos);
}

// The server keeps a writable mapping and rewrites slot_count after the
// client checked it: 0 was SIGFPE, 2^31 SIGSEGV in the old reader.
TEST(ChannelAttacks, ASlotCountRewrittenAfterTheCheckDoesNotCrashTheReader) {
    FakeServer server;
    RingBlock block;
    server.offer(&block);
    auto client = gc::Client::connect(server.path());
    auto channel = client.attitude_channel();
    for (std::uint64_t seq = 1; seq <= 5; ++seq) {
        block.publish(seq);
    }
    EXPECT_EQ(channel.next(1s)->seq, 5U);
    std::uint64_t seq = 5;
    for (const std::uint32_t hostile : {0U, 1U << 31, 3U, 0xffffffffU}) {
        block.set_header(4, hostile);  // slot_count
        EXPECT_EQ(channel.latest()->seq, seq);
        block.publish(++seq);
        EXPECT_EQ(channel.next(1s)->seq, seq);
        channel = client.attitude_channel();  // a new reader of the same mapping
        EXPECT_EQ(channel.next(1s)->seq, seq);
    }
    block.set_header(8, 0xffffffffU);  // published's low word: far beyond the ring
    block.set_header(9, 0x7fffffffU);
    EXPECT_FALSE(channel.latest());
    EXPECT_FALSE(channel.next(10ms));
}

TEST(ChannelAttacks, MoreDescriptorsThanAnnouncedAreClosedAtOnce) {
    FakeServer server;
    RingBlock block;
    int pipe_fds[2];
    ASSERT_EQ(::pipe(pipe_fds), 0);
    server.offer(
        Offer{&block,
              std::vector<int>{block.fd(), block.wake_fd(), pipe_fds[0], pipe_fds[1], pipe_fds[0]},
              {}});
    const auto before = open_descriptors();
    {
        auto client = gc::Client::connect(server.path());
        auto channel = client.attitude_channel();
        block.publish(3);
        EXPECT_EQ(channel.next(1s)->seq, 3U);
        // The client's socket and the fake's end of it: none of the five kept.
        EXPECT_EQ(open_descriptors(), before + 2);
    }
    EXPECT_EQ(settled(before), before);
    ::close(pipe_fds[0]);
    ::close(pipe_fds[1]);
}

TEST(ChannelAttacks, DescriptorsZeroOnAConnectionWithoutAChannelIsAClearError) {
    FakeServer server;  // no offer: "descriptors":0
    auto client = gc::Client::connect(server.path());
    EXPECT_NE(bad_reply([&] {
                  client.attitude_channel();
              }).find("this connection has none; reconnect to get them"),
              std::string::npos);
}

// Before: every descriptor attached to a notification stayed open until the
// connection closed (3,000 notifications: 3,006 open descriptors).
TEST(ChannelAttacks, NotificationsCarryingPipesLeaveTheDescriptorCountFlat) {
    FakeServer server;
    int pipe_fds[2];
    ASSERT_EQ(::pipe(pipe_fds), 0);
    const nlohmann::json note = {
        {"jsonrpc", "2.0"}, {"method", "link"}, {"params", {{"state", "up"}}}};
    const auto before = open_descriptors();
    {
        auto client = gc::Client::connect(server.path());
        client.subscribe({"link"});  // the fake has accepted us
        const auto connected = open_descriptors();
        std::thread flood([&] {
            for (int i = 0; i < 3000; ++i) {
                server.push(note, {pipe_fds[0], pipe_fds[1]});
            }
        });
        std::size_t most = 0;
        for (int i = 0; i < 3000; ++i) {
            ASSERT_TRUE(client.next_notification(5s));
            most = std::max(most, open_descriptors());
        }
        flood.join();
        // Flat: each recvmsg's pair is closed before its line is handled.
        EXPECT_EQ(most, connected);
    }
    EXPECT_EQ(settled(before), before);
    ::close(pipe_fds[0]);
    ::close(pipe_fds[1]);
}

TEST(ChannelAttacks, AsyncClientClosesDescriptorsOnNotificationsToo) {
    FakeServer server;
    int pipe_fds[2];
    ASSERT_EQ(::pipe(pipe_fds), 0);
    const nlohmann::json note = {
        {"jsonrpc", "2.0"}, {"method", "link"}, {"params", {{"state", "up"}}}};
    boost::asio::io_context io;
    gc::AsyncClient client(io);
    int notes = 0;
    std::size_t first = 0;
    std::size_t most = 0;
    client.on_notification([&](const gc::Notification&) {
        const auto now = open_descriptors();
        first = first == 0 ? now : first;
        most = std::max(most, now);
        if (++notes == 3000) {
            client.close();
        }
    });
    std::thread flood;
    client.async_connect(server.path(), [&](std::optional<gc::Error> error) {
        ASSERT_FALSE(error);
        flood = std::thread([&] {
            for (int i = 0; i < 3000; ++i) {
                server.push(note, {pipe_fds[0], pipe_fds[1]});
            }
        });
    });
    io.run_for(30s);
    flood.join();
    EXPECT_EQ(notes, 3000);
    // Flat: each recvmsg's pair is closed before its line is handled (3,000
    // kept pairs would be 6,000 more). The count is the whole process's, the
    // fake server's thread included, which may hold one more for an instant
    // (seen once under ASan): a margin of 2, as the Python test has 4.
    EXPECT_LE(most, first + 2);
    ::close(pipe_fds[0]);
    ::close(pipe_fds[1]);
}

bool timed_out(const std::function<void()>& f) {
    try {
        f();
    } catch (const gc::Error& e) {
        return e.is(gc::ErrorCode::kTimeout);
    }
    return false;
}

// Review finding 6. Before: each timed-out attitude_channel call let two
// more descriptors stay (3 timeouts: the 6 pipes of one notification and
// the 6 descriptors of the late replies stayed open until disconnect).
TEST(ChannelAttacks, TimedOutChannelCallsLeaveNoRoomForDescriptors) {
    FakeServer server;
    RingBlock block;
    for (int i = 0; i < 3; ++i) {
        server.offer(Offer{&block, std::nullopt, {}, true});  // answered late
    }
    int pipe_fds[2];
    ASSERT_EQ(::pipe(pipe_fds), 0);
    const nlohmann::json note = {
        {"jsonrpc", "2.0"}, {"method", "link"}, {"params", {{"state", "up"}}}};
    const auto before = open_descriptors();
    {
        auto client = gc::Client::connect(server.path());
        client.subscribe({"link"});  // the fake has accepted us
        const auto connected = open_descriptors();
        client.set_call_timeout(50ms);
        for (int i = 0; i < 3; ++i) {
            EXPECT_TRUE(timed_out([&] { client.attitude_channel(); }));
        }
        server.push(note,
                    {pipe_fds[0], pipe_fds[1], pipe_fds[0], pipe_fds[1], pipe_fds[0], pipe_fds[1]});
        ASSERT_TRUE(client.next_notification(5s));
        EXPECT_EQ(open_descriptors(), connected);
        server.release_held();  // the three late replies, two descriptors each
        server.push(note);
        ASSERT_TRUE(client.next_notification(5s));
        EXPECT_EQ(open_descriptors(), connected);
    }
    EXPECT_EQ(settled(before), before);
    ::close(pipe_fds[0]);
    ::close(pipe_fds[1]);
}

// Before: the late reply's descriptors were kept too and the next reply
// claimed them: the channel was the abandoned request's block (here: one
// that never publishes) and the right one's descriptors stayed open.
TEST(ChannelAttacks, ALateChannelReplyIsClosedAndTheAwaitedOneMapped) {
    FakeServer server;
    RingBlock abandoned;
    RingBlock awaited;
    server.offer(Offer{&abandoned, std::nullopt, {}, true});
    server.offer(&awaited);  // answered after the late reply
    auto client = gc::Client::connect(server.path());
    client.subscribe({"link"});
    const auto connected = open_descriptors();
    client.set_call_timeout(50ms);
    EXPECT_TRUE(timed_out([&] { client.attitude_channel(); }));
    client.set_call_timeout(5s);
    auto channel = client.attitude_channel();
    EXPECT_EQ(open_descriptors(), connected);
    awaited.publish(7);
    const auto sample = channel.next(1s);
    ASSERT_TRUE(sample);
    EXPECT_EQ(sample->seq, 7U);
}

TEST(ChannelAttacks, AsyncClientClosesALateChannelReplyToo) {
    FakeServer server;
    RingBlock abandoned;
    RingBlock awaited;
    server.offer(Offer{&abandoned, std::nullopt, {}, true});
    server.offer(&awaited);
    boost::asio::io_context io;
    gc::AsyncClient client(io);
    client.set_call_timeout(50ms);
    std::size_t connected = 0;
    std::size_t after = 0;
    bool first_timed_out = false;
    std::optional<gc::AttitudeChannel> channel;
    client.async_connect(server.path(), [&](std::optional<gc::Error> error) {
        ASSERT_FALSE(error);
        client.async_subscribe({"link"}, std::nullopt, [&](auto, auto) {
            connected = open_descriptors();
            client.async_attitude_channel([&](std::optional<gc::Error> e, gc::AttitudeChannel) {
                first_timed_out = e && e->is(gc::ErrorCode::kTimeout);
                client.set_call_timeout(5s);
                client.async_attitude_channel(
                    [&](std::optional<gc::Error> e2, gc::AttitudeChannel c) {
                        EXPECT_FALSE(e2) << e2->message();
                        after = open_descriptors();
                        channel = std::move(c);
                        client.close();
                    });
            });
        });
    });
    io.run_for(30s);
    EXPECT_TRUE(first_timed_out);
    EXPECT_EQ(after, connected);
    ASSERT_TRUE(channel);
    awaited.publish(9);
    const auto sample = channel->next(1s);
    ASSERT_TRUE(sample);
    EXPECT_EQ(sample->seq, 9U);
}

// The C entry point other languages read the ring with (ring_read.h).
TEST(ChannelAttacks, GportRingReadGivesWholeSamplesAndNothingForTheRest) {
    RingBlock block(8);
    for (std::uint64_t seq = 1; seq <= 10; ++seq) {
        block.publish(seq, seq % 2 == 0);
    }
    void* memory = ::mmap(nullptr, block.size(), PROT_READ, MAP_SHARED, block.fd(), 0);
    ASSERT_NE(memory, MAP_FAILED);
    std::uint64_t words[15] = {};
    ASSERT_EQ(gport_ring_read(memory, 8, 10, words), 1);
    EXPECT_EQ(words[0], 10U);                                 // the sample's seq
    EXPECT_DOUBLE_EQ(std::bit_cast<double>(words[2]), 1.0);   // imu roll = seq / 10
    EXPECT_EQ(words[8], 1U);                                  // has_rates
    EXPECT_DOUBLE_EQ(std::bit_cast<double>(words[14]), 6.0);  // imu rate z
    EXPECT_EQ(gport_ring_read(memory, 8, 2, words), 0);       // overwritten (8 slots)
    EXPECT_EQ(gport_ring_read(memory, 8, 11, words), 0);      // not written yet
    EXPECT_EQ(gport_ring_read(memory, 8, 0, words), 0);
    EXPECT_EQ(gport_ring_read(memory, 0, 10, words), 0);  // no slot count: no division
    EXPECT_EQ(gport_ring_read(nullptr, 8, 10, words), 0);
    EXPECT_EQ(gport_ring_read(memory, 8, 10, nullptr), 0);
    EXPECT_EQ(gport_client_abi_minor(), 11U);
    ::munmap(memory, block.size());
}

// The acquire loads other languages order their looks with (ring_read.h).
TEST(ChannelAttacks, TheCLoadsReadPublishedTheFlagsAndTheWakeWord) {
    RingBlock block(8);
    void* ring = ::mmap(nullptr, block.size(), PROT_READ, MAP_SHARED, block.fd(), 0);
    void* wake = ::mmap(nullptr, base::kWakeBlockBytes, PROT_READ, MAP_SHARED, block.wake_fd(), 0);
    ASSERT_NE(ring, MAP_FAILED);
    ASSERT_NE(wake, MAP_FAILED);
    EXPECT_EQ(gport_ring_published(ring), 0U);
    EXPECT_EQ(gport_wake_word(wake), 0U);
    for (std::uint64_t seq = 1; seq <= 10; ++seq) {
        block.publish(seq);
    }
    EXPECT_EQ(gport_ring_published(ring), 10U);
    EXPECT_EQ(gport_wake_word(wake), 10U);
    EXPECT_EQ(gport_ring_flags(ring), 0U);
    block.close();
    EXPECT_EQ(gport_ring_flags(ring) & GPORT_RING_FLAG_CLOSED, GPORT_RING_FLAG_CLOSED);
    EXPECT_EQ(gport_wake_word(wake), 11U);
    EXPECT_EQ(gport_ring_published(nullptr), 0U);
    EXPECT_EQ(gport_ring_flags(nullptr), 0U);
    EXPECT_EQ(gport_wake_word(nullptr), 0U);
    ::munmap(ring, block.size());
    ::munmap(wake, base::kWakeBlockBytes);
}

}  // namespace
}  // namespace gport::testing
