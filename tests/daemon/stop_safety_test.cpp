// Issue 10, "a stop always reaches the gimbal": stops with a stuck line, stops
// by a client that lost control, an observer that calls back into the core,
// and the caps on settings requests. The simulated gimbal stops draining the
// line on demand (pause_reading), which fills the kernel's pty buffer and
// then the daemon's write queue.
#include <algorithm>

#include "core_fixture.hpp"

namespace gport::testing {
namespace {

using daemon::EndReason;
using daemon::ErrorCode;
using daemon::LinkState;
using daemon::MotionChange;

class StopSafety : public CoreFixture {
  protected:
    // Stalls the gimbal's side of the line and queues photos until one is
    // refused: the kernel's buffer and the daemon's queue are then full.
    void stall_line() {
        simulator->pause_reading();
        for (int i = 0; i < 200000; ++i) {
            if (!core->photo(alice).ok()) {
                return;
            }
            io.poll();
        }
        FAIL() << "the line never filled up";
    }

    // Index in the trace of the first 0x85 zero speed, or trace.size().
    std::size_t first_stop() const {
        const auto it = std::ranges::find_if(trace, [](const Json& t) {
            return t.value("cmd", "") == "0x85" && t.value("mode", "") == "speed" &&
                   t["speed"] == Json::array({0, 0, 0});
        });
        return static_cast<std::size_t>(it - trace.begin());
    }

    std::size_t last_photo() const {
        std::size_t last = 0;
        for (std::size_t i = 0; i < trace.size(); ++i) {
            if (trace[i].value("action", "") == "photo") {
                last = i;
            }
        }
        return last;
    }

    bool ended_with(EndReason reason) const {
        return !recorder.motions.empty() &&
               recorder.motions.back().change == MotionChange::kEnded &&
               recorder.motions.back().reason == reason;
    }
};

TEST_F(StopSafety, AStopGoesNextEvenWhenTheQueueIsFullAndSpeedsCoalesce) {
    start();
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    ASSERT_NO_FATAL_FAILURE(stall_line());
    for (int i = 0; i < 96; ++i) {
        auto r = core->speed(alice, {0, 0, static_cast<std::int16_t>(100 + i)}, 30000ms);
        ASSERT_TRUE(r.ok()) << "speed " << i << ": " << r.error().message;
    }
    auto stopped = core->stop(alice);
    ASSERT_TRUE(stopped.ok()) << stopped.error().message;
    EXPECT_TRUE(ended_with(EndReason::kStop));
    EXPECT_FALSE(core->status().motion.has_value());
    EXPECT_GE(core->status().counters.frames_replaced, 95U) << "waiting speeds were replaced";

    simulator->resume_reading();
    ASSERT_TRUE(run_until([&] { return first_stop() < trace.size(); }));
    ASSERT_TRUE(run_until([&] { return core->status().counters.stops_sent == 1; }));
    run_for(300ms);
    EXPECT_LT(first_stop(), last_photo()) << "the stop overtook the waiting photos";
    const auto speeds = speed_frames();
    EXPECT_EQ(speeds.back(), Json::array({0, 0, 0})) << "no speed after the stop";
    EXPECT_LE(speeds.size(), 3U) << "at most the speed before the stall and the one being "
                                    "written went out before the stop";
}

TEST_F(StopSafety, TheDeadmanStopsWhenTheLineIsStuck) {
    start();
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    ASSERT_TRUE(core->speed(alice, {0, 1000, 0}, 30000ms).ok());
    ASSERT_NO_FATAL_FAILURE(stall_line());
    auto stopped = core->stop(bob);  // someone else's stop, also accepted
    EXPECT_TRUE(stopped.ok()) << stopped.error().message;
    ASSERT_TRUE(core->speed(alice, {0, 1000, 0}, 30000ms).ok());
    core->client_gone(alice);
    EXPECT_TRUE(ended_with(EndReason::kOwnerGone));
    simulator->resume_reading();
    ASSERT_TRUE(run_until([&] { return core->status().counters.stops_sent >= 1; }));
    run_for(300ms);
    EXPECT_EQ(speed_frames().back(), Json::array({0, 0, 0}));
    EXPECT_EQ(core->status().counters.stops_sent, zero_speed_frames());
}

TEST_F(StopSafety, ShutdownWithAStuckLineQueuesTheStopNext) {
    start();
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    ASSERT_TRUE(core->speed(alice, {1000, 0, 0}, 30000ms).ok());
    ASSERT_NO_FATAL_FAILURE(stall_line());
    bool done = false;
    core->shutdown([&] { done = true; });
    EXPECT_TRUE(ended_with(EndReason::kShutdown));
    simulator->resume_reading();  // within the drain limit (500 ms)
    ASSERT_TRUE(run_until([&] { return done; }));
    ASSERT_TRUE(run_until([&] { return zero_speed_frames() == 1; }));
    EXPECT_LT(first_stop(), last_photo()) << "the stop overtook the waiting photos";
    core.reset();
}

// A stop that cannot be written because the device is closed is owed: it is
// the first control frame the gimbal gets when the device is back.
TEST_F(StopSafety, AStopWhileTheDeviceIsClosedIsSentFirstWhenItReopens) {
    sim::SimOptions options;
    options.link_path = ::testing::TempDir() + "gport-stop-owed-" + std::to_string(::getpid());
    options.faults.vanish_every = 600ms;
    options.faults.vanish_for = 300ms;
    start(options);
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    ASSERT_TRUE(run_until([&] { return !core->status().device_open; }));
    auto stopped = core->stop(alice);
    ASSERT_FALSE(stopped.ok());
    EXPECT_EQ(stopped.error().code, ErrorCode::kLinkDown);
    EXPECT_NE(stopped.error().message.find("reopens"), std::string::npos);
    ASSERT_TRUE(run_until([&] { return zero_speed_frames() == 1; }));
    EXPECT_EQ(trace_of("0x85").front()["speed"], Json::array({0, 0, 0}));
    EXPECT_EQ(core->status().counters.stops_sent, 1U);
}

TEST_F(StopSafety, TheOwnerMayStopAfterAnotherClientAcquiresWhichPreemptsIt) {
    start();
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    ASSERT_TRUE(core->speed(alice, {0, 0, 2000}, 30000ms).ok());
    ASSERT_TRUE(core->acquire(bob).ok());
    EXPECT_TRUE(ended_with(EndReason::kPreempted));
    EXPECT_EQ(recorder.motions.back().owner->id, alice.id);
    ASSERT_TRUE(run_until([&] { return zero_speed_frames() == 1; }));
    auto r = core->stop(alice);
    EXPECT_TRUE(r.ok()) << r.error().message;
    EXPECT_FALSE(core->speed(alice, {0, 0, 100}, std::nullopt).ok()) << "speed still arbitrated";
    ASSERT_TRUE(core->release(bob).ok());
    const auto replaced = core->status().counters.frames_replaced;
    r = core->stop(alice);
    EXPECT_TRUE(r.ok()) << r.error().message;
    // Both stops reach the wire, but the second may find the first still
    // waiting in the write queue (a slow line; most runs under qemu-user)
    // and be merged with it (counted as replaced): three zero frames, or two
    // and one merge.
    const auto merged = [&] { return core->status().counters.frames_replaced - replaced; };
    ASSERT_TRUE(run_until([&] { return zero_speed_frames() + merged() == 3; }));
    EXPECT_EQ(speed_frames().back(), Json::array({0, 0, 0}));
}

TEST_F(StopSafety, AcquiringKeepsTheHoldersOwnMotion) {
    start();
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    ASSERT_TRUE(core->speed(alice, {0, 0, 2000}, 30000ms).ok());
    ASSERT_TRUE(core->acquire(alice).ok());
    EXPECT_TRUE(core->status().motion.has_value());
}

// Calls back into the core from inside the events it emits, as the socket
// server does when the owner's outbox overflows with its own notification.
struct Reentrant : Recorder {
    daemon::Core* core = nullptr;
    std::optional<daemon::ClientInfo> drop_on_start;
    void on_motion(const daemon::MotionEvent& e) override {
        Recorder::on_motion(e);
        if (e.change != MotionChange::kEnded && drop_on_start && e.owner &&
            e.owner->id == drop_on_start->id) {
            core->client_gone(*e.owner);
            core->client_closed(*e.owner);
        }
    }
};

TEST_F(StopSafety, AnObserverMayDropTheOwnerFromInsideItsStartedEvent) {
    Reentrant observer;
    start();
    observer.core = core.get();
    core->set_observer(&observer);
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    observer.drop_on_start = alice;
    auto r = core->speed(alice, {0, 0, 1500}, 30000ms);
    ASSERT_TRUE(r.ok());
    ASSERT_EQ(observer.motions.size(), 2U);
    EXPECT_EQ(observer.motions[0].change, MotionChange::kStarted);
    EXPECT_EQ(observer.motions[1].reason, EndReason::kOwnerGone);
    EXPECT_FALSE(core->status().motion.has_value());
    ASSERT_TRUE(run_until([&] { return zero_speed_frames() == 1; }));
    const auto sent = speed_frames().size();
    run_for(400ms);
    EXPECT_EQ(speed_frames().size(), sent) << "no keepalive for a motion that ended";
    observer.drop_on_start.reset();
    ASSERT_TRUE(core->speed(bob, {0, 0, 700}, 400ms).ok());  // the core still works
    ASSERT_TRUE(run_until([&] { return zero_speed_frames() == 2; }));
    EXPECT_TRUE(observer.motions.back().reason == EndReason::kDuration);
    core->set_observer(&recorder);
}

// A settings request whose frame cannot be queued (the line is stuck) fails
// later, from the loop: never inside the call that made it.
TEST_F(StopSafety, ASettingsResultNeverArrivesInsideTheRequest) {
    start();
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    ASSERT_NO_FATAL_FAILURE(stall_line());
    bool requesting = true;
    std::optional<bool> called_inside;
    core->get_settings(alice, [&](daemon::Outcome<daemon::Settings> r) {
        called_inside = requesting;
        EXPECT_EQ(r.error().code, ErrorCode::kLinkDown);
    });
    requesting = false;
    ASSERT_TRUE(run_until([&] { return called_inside.has_value(); }));
    EXPECT_FALSE(*called_inside);
}

TEST_F(StopSafety, SettingsRequestsAreCappedPerClientAndInTotal) {
    start();
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    simulator->pause_reading();  // a gimbal that never answers
    std::vector<daemon::Outcome<daemon::Settings>> refused;
    auto keep = [&](daemon::Outcome<daemon::Settings> r) {
        if (!r.ok() && r.error().code == ErrorCode::kTooManyRequests) {
            refused.push_back(r);
        }
    };
    for (int i = 0; i < 5; ++i) {
        core->get_settings(alice, keep);
    }
    ASSERT_TRUE(run_until([&] { return refused.size() == 1; }));
    EXPECT_NE(refused[0].error().message.find("4 per client"), std::string::npos)
        << refused[0].error().message;
    for (std::uint64_t id = 10; id < 25; ++id) {  // 15 more clients, 4 each: 64 in all
        for (int i = 0; i < 4; ++i) {
            core->get_settings({id, 1, 1, 1, {}}, keep);
        }
    }
    core->get_settings(bob, keep);
    ASSERT_TRUE(run_until([&] { return refused.size() == 2; }));
    EXPECT_NE(refused[1].error().message.find("64 from all clients"), std::string::npos)
        << refused[1].error().message;
}

TEST_F(StopSafety, AClosedClientsSettingsRequestsAreDroppedWithoutCallbacks) {
    start();
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    simulator->pause_reading();
    int alice_calls = 0;
    for (int i = 0; i < 3; ++i) {
        core->get_settings(alice, [&](daemon::Outcome<daemon::Settings>) { ++alice_calls; });
    }
    std::optional<daemon::Outcome<daemon::Settings>> bobs;
    core->get_settings(bob, [&](daemon::Outcome<daemon::Settings> r) { bobs = r; });
    core->client_gone(alice);  // the deadman: settings go on
    core->client_closed(alice);
    // Alice's running request finishes (2 x 150 ms), then bob's runs at once.
    ASSERT_TRUE(run_until([&] { return bobs.has_value(); }));
    EXPECT_EQ(bobs->error().code, ErrorCode::kNoAnswer);
    EXPECT_EQ(alice_calls, 0);
    EXPECT_EQ(core->status().counters.settings_timeouts, 4U) << "alice's first and bob's";
}

}  // namespace
}  // namespace gport::testing
