// The shared-memory attitude channel end to end: libgport-client against the
// real gportd on gport-sim (a separate process on a pty) or --simulate.
#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <csignal>
#include <filesystem>
#include <map>

#include "client_fixture.hpp"
#include "gport/client/async_client.hpp"

namespace gport::testing {
namespace {

std::size_t open_descriptors() {
    std::size_t n = 0;
    for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator("/proc/self/fd")) {
        ++n;
    }
    return n;
}

// Every sample the ring gives is the socket's notification of the same seq,
// value for value.
TEST(AttitudeChannelDaemon, RingSamplesMatchTheSocketNotificationsOfTheSameSeq) {
    TempDir dir;
    SimProcess sim(dir);
    DaemonProcess daemon(dir, {"--device", sim.link()});
    auto socket_reader = connect_when_ready(daemon.socket());
    ASSERT_TRUE(link_is(socket_reader, "up"));
    socket_reader.subscribe({"attitude"});
    auto ring_reader = connect_when_ready(daemon.socket());
    const auto sub = ring_reader.subscribe({"attitude", "link"}, gc::SubscribeOptions{{}, true});
    EXPECT_EQ(sub.topics, (std::vector<std::string>{"link", "attitude"}));
    std::vector<gc::AttitudeSample> ring;
    while (ring.size() < 5) {
        auto sample = next_of<gc::AttitudeSample>(ring_reader);
        ASSERT_TRUE(sample) << "no sample from the ring";
        ring.push_back(*sample);
    }
    for (std::size_t i = 1; i < ring.size(); ++i) {
        EXPECT_GT(ring[i].seq, ring[i - 1].seq);
    }
    std::map<std::uint64_t, gc::AttitudeSample> socket;
    while (socket.empty() || socket.rbegin()->first < ring.back().seq) {
        auto sample = next_of<gc::AttitudeSample>(socket_reader);
        ASSERT_TRUE(sample) << "no sample from the socket";
        socket[sample->seq] = *sample;
    }
    // A socket subscriber may lose samples on a loaded machine (counted in
    // `dropped`); every one it has must match the ring's.
    std::size_t common = 0;
    for (const auto& r : ring) {
        const auto it = socket.find(r.seq);
        if (it == socket.end()) {
            continue;
        }
        ++common;
        EXPECT_DOUBLE_EQ(r.time, it->second.time);
        EXPECT_DOUBLE_EQ(r.imu.roll, it->second.imu.roll);
        EXPECT_DOUBLE_EQ(r.imu.pitch, it->second.imu.pitch);
        EXPECT_DOUBLE_EQ(r.imu.yaw, it->second.imu.yaw);
        EXPECT_DOUBLE_EQ(r.hall.yaw, it->second.hall.yaw);
        EXPECT_EQ(r.rates.has_value(), it->second.rates.has_value());
    }
    EXPECT_GE(common, 3U);
}

TEST(AttitudeChannelDaemon, LinkNotificationsStillArriveOnTheSocket) {
    TempDir dir;
    auto sim = std::make_unique<SimProcess>(dir);
    DaemonProcess daemon(dir, {"--device", sim->link()});
    auto client = connect_when_ready(daemon.socket());
    ASSERT_TRUE(link_is(client, "up"));
    client.subscribe({"attitude", "link"}, gc::SubscribeOptions{{}, true});
    ASSERT_TRUE(next_of<gc::AttitudeSample>(client));
    sim.reset();  // the gimbal goes away
    const auto event = next_of<gc::LinkEvent>(client);
    ASSERT_TRUE(event) << "no link event";
    EXPECT_NE(event->state, "up");
}

TEST(AttitudeChannelDaemon, ADaemonRestartClosesTheChannelAndANewOneWorks) {
    TempDir dir;
    auto daemon = std::make_unique<DaemonProcess>(dir, std::vector<std::string>{"--simulate"});
    auto client = connect_when_ready(daemon->socket());
    ASSERT_TRUE(link_is(client, "up"));
    auto channel = client.attitude_channel();
    ASSERT_TRUE(channel.next(10s));
    EXPECT_FALSE(channel.closed());
    daemon->process().signal(SIGTERM);  // gportd closes the ring before the socket
    EXPECT_TRUE(daemon->process().wait().has_value());
    EXPECT_TRUE(channel.closed());
    while (channel.next(0ms)) {
    }
    EXPECT_FALSE(channel.next(100ms));
    EXPECT_TRUE(channel.latest());  // the mapping is ours: the last samples stay

    daemon.reset();
    daemon = std::make_unique<DaemonProcess>(dir, std::vector<std::string>{"--simulate"});
    auto again = connect_when_ready(daemon->socket());
    ASSERT_TRUE(link_is(again, "up"));
    again.subscribe({"attitude"}, gc::SubscribeOptions{{}, true});
    EXPECT_TRUE(next_of<gc::AttitudeSample>(again));
}

TEST(AttitudeChannelDaemon, OpeningAndClosingChannelsLeaksNoDescriptor) {
    TempDir dir;
    DaemonProcess daemon(dir, {"--simulate"});
    { auto warm = connect_when_ready(daemon.socket()); }
    const auto before = open_descriptors();
    for (int i = 0; i < 5; ++i) {
        auto client = gc::Client::connect(daemon.socket());
        auto channel = client.attitude_channel();
        client.subscribe({"attitude"}, gc::SubscribeOptions{{}, true});
        EXPECT_TRUE(next_of<gc::AttitudeSample>(client));
    }
    EXPECT_EQ(open_descriptors(), before);
}

TEST(AttitudeChannelDaemon, AsyncClientDeliversRingSamplesAndSocketEvents) {
    TempDir dir;
    DaemonProcess daemon(dir, {"--simulate"});
    { auto ready = connect_when_ready(daemon.socket()); }
    boost::asio::io_context io;
    gc::AsyncClient client(io);
    boost::asio::steady_timer guard(io, 20s);
    guard.async_wait([&](auto) { client.close(); });
    std::vector<std::uint64_t> seqs;
    bool motion = false;
    client.on_notification([&](const gc::Notification& n) {
        if (const auto* a = std::get_if<gc::AttitudeSample>(&n)) {
            seqs.push_back(a->seq);
            if (seqs.size() == 3) {
                client.async_speed({.yaw = 5}, {.duration = 1000ms}, [](auto, auto) {});
            }
        } else if (std::holds_alternative<gc::MotionEvent>(n)) {
            motion = true;
        }
        if (motion && seqs.size() >= 3) {
            client.close();
            guard.cancel();
        }
    });
    client.async_connect(daemon.socket(), [&](std::optional<gc::Error> error) {
        ASSERT_FALSE(error);
        client.async_subscribe(
            {"attitude", "motion"}, gc::SubscribeOptions{{}, true},
            [](std::optional<gc::Error> e, gc::Subscription) { ASSERT_FALSE(e) << e->what(); });
    });
    io.run();
    ASSERT_GE(seqs.size(), 3U);
    for (std::size_t i = 1; i < seqs.size(); ++i) {
        EXPECT_GT(seqs[i], seqs[i - 1]);
    }
    EXPECT_TRUE(motion) << "no motion event from the socket";
}

}  // namespace
}  // namespace gport::testing
