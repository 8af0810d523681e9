// Subscriptions of the blocking Client: pulled with next_notification() or
// pushed to a callback.
#include <unistd.h>

#include "client_fixture.hpp"

namespace gport::testing {
namespace {

using ClientNotifications = SimulatedDaemonTest;

TEST_F(ClientNotifications, AttitudeSamplesArePulled) {
    const auto sub = client().subscribe({"attitude"}, 20);
    EXPECT_EQ(sub.topics, std::vector<std::string>{"attitude"});
    ASSERT_TRUE(sub.max_rate_hz.has_value());
    EXPECT_EQ(*sub.max_rate_hz, 20);
    const auto first = next_of<gc::AttitudeSample>(client());
    const auto second = next_of<gc::AttitudeSample>(client());
    ASSERT_TRUE(first && second);
    EXPECT_GT(second->seq, first->seq);
    EXPECT_GT(first->time, 1.6e9);
    EXPECT_FALSE(first->age_ms.has_value()) << "only the attitude method has an age";
    EXPECT_TRUE(client().unsubscribe().topics.empty());
}

TEST_F(ClientNotifications, NothingArrivesWithinTheTimeoutWithoutASubscription) {
    EXPECT_FALSE(client().next_notification(200ms).has_value());
}

TEST_F(ClientNotifications, CallbackGetsSamplesDuringDispatchAndCalls) {
    std::vector<gc::AttitudeSample> samples;
    client().on_notification([&](const gc::Notification& n) {
        if (const auto* s = std::get_if<gc::AttitudeSample>(&n)) {
            samples.push_back(*s);
        }
    });
    client().subscribe({"attitude"}, 50);
    EXPECT_TRUE(eventually([&] {
        client().dispatch(100ms);
        return samples.size() >= 3;
    }));
    const auto before = samples.size();
    EXPECT_TRUE(eventually([&] {
        client().status();  // samples arriving during a call reach the callback too
        return samples.size() > before;
    }));
    client().on_notification(nullptr);
    client().unsubscribe({"attitude"});
}

TEST_F(ClientNotifications, MotionEventsOfASpeedMotion) {
    client().subscribe({"motion"});
    client().speed({.pitch = 5}, 3000ms);
    const auto started = next_motion(client(), "started");
    ASSERT_TRUE(started.has_value());
    EXPECT_EQ(started->mode, "speed");
    ASSERT_TRUE(started->speed.has_value());
    EXPECT_EQ(started->speed->pitch, 5);
    EXPECT_EQ(started->duration_ms, 3000);
    ASSERT_TRUE(started->owner.has_value());
    EXPECT_EQ(started->owner->pid, ::getpid());
    client().stop();
    const auto ended = next_motion(client(), "ended");
    ASSERT_TRUE(ended.has_value());
    EXPECT_EQ(ended->reason, "stop");
}

// gportd on gport-sim (a separate process): when the simulated gimbal
// exits, the link leaves "up" and subscribers hear of it.
TEST(ClientLinkEvents, LinkLeavesUpWhenTheGimbalGoesAway) {
    TempDir dir;
    auto sim = std::make_unique<SimProcess>(dir);
    DaemonProcess daemon(dir, {"--device", sim->link()});
    auto client = connect_when_ready(daemon.socket());
    ASSERT_TRUE(link_is(client, "up"));
    client.subscribe({"link"});
    sim.reset();  // SIGTERM: the pty closes
    const auto event = next_of<gc::LinkEvent>(client);
    ASSERT_TRUE(event.has_value()) << "no link event";
    EXPECT_NE(event->state, "up");
    EXPECT_FALSE(event->reason.empty());
}

}  // namespace
}  // namespace gport::testing
