// The daemon core against the simulated gimbal over a pty: link health,
// keepalive and deadman, settings, arbitration, access and robustness.
// Timing assertions are deliberately loose: the machine is small and noisy.
#include <pty.h>
#include <unistd.h>

#include "core_fixture.hpp"

namespace gport::testing {
namespace {

using daemon::EndReason;
using daemon::ErrorCode;
using daemon::LinkState;
using daemon::MotionChange;

TEST_F(CoreFixture, AttitudeFlowsAndLinkComesUp) {
    start();
    ASSERT_TRUE(run_until([&] { return recorder.attitude.size() >= 10; }));
    EXPECT_TRUE(link_up());
    for (std::size_t i = 1; i < recorder.attitude.size(); ++i) {
        EXPECT_EQ(recorder.attitude[i].seq, recorder.attitude[i - 1].seq + 1);
    }
    ASSERT_TRUE(core->latest_attitude().has_value());
    const auto status = core->status();
    EXPECT_TRUE(status.device_open);
    EXPECT_GE(status.counters.attitude_frames, 10U);
    EXPECT_EQ(status.counters.crc_errors, 0U);
    ASSERT_FALSE(recorder.links.empty());
    EXPECT_EQ(recorder.links.back().state, LinkState::kUp);
}

TEST_F(CoreFixture, SpeedIsKeptAliveForItsDurationThenStopped) {
    start();
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    auto started = core->speed(alice, {0, 0, 3000}, 1000ms);
    ASSERT_TRUE(started.ok()) << started.error().message;
    EXPECT_EQ(started->duration, 1000ms);
    ASSERT_TRUE(run_until([&] { return zero_speed_frames() >= 1; }, 5s));
    const auto frames = speed_frames();
    // One at once, then ~10 Hz for 1 s: about 10 moving frames, then a stop.
    const auto moving = frames.size() - zero_speed_frames();
    EXPECT_GE(moving, 7U);
    EXPECT_LE(moving, 13U);
    EXPECT_EQ(frames.back(), Json::array({0, 0, 0}));
    EXPECT_EQ(frames.front(), Json::array({0, 0, 3000}));
    ASSERT_GE(recorder.motions.size(), 2U);
    EXPECT_EQ(recorder.motions.front().change, MotionChange::kStarted);
    EXPECT_EQ(recorder.motions.back().change, MotionChange::kEnded);
    EXPECT_EQ(recorder.motions.back().reason, EndReason::kDuration);
    EXPECT_FALSE(core->status().motion.has_value());
}

TEST_F(CoreFixture, DeadmanStopsWhenTheOwnerGoes) {
    start();
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    ASSERT_TRUE(core->speed(alice, {0, 1000, 0}, 30000ms).ok());
    run_for(300ms);
    EXPECT_EQ(zero_speed_frames(), 0U);
    core->client_gone(bob);  // someone else leaving changes nothing
    run_for(150ms);
    EXPECT_EQ(zero_speed_frames(), 0U);
    core->client_gone(alice);
    ASSERT_TRUE(run_until([&] { return zero_speed_frames() == 1; }, 5s));
    EXPECT_EQ(recorder.motions.back().reason, EndReason::kOwnerGone);
    const auto before = speed_frames().size();
    run_for(400ms);
    EXPECT_EQ(speed_frames().size(), before) << "keepalive must end with its owner";
}

// Every stop is followed on the wire by a zero speed; one that finds a stop
// still waiting (not yet written) is that stop. stops_sent counts what went
// on the wire, so it matches the gimbal's count.
TEST_F(CoreFixture, EveryStopReachesTheWireAndWaitingStopsCoalesce) {
    start();
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    for (int i = 0; i < 3; ++i) {
        ASSERT_TRUE(core->stop(alice).ok());  // one written, one waiting, one coalesced
    }
    ASSERT_TRUE(run_until([&] { return zero_speed_frames() == 2; }, 5s));
    ASSERT_TRUE(run_until([&] { return core->status().counters.stops_sent == 2; }, 5s));
    EXPECT_EQ(core->status().counters.frames_replaced, 1U);
    ASSERT_TRUE(core->stop(alice).ok());  // the line is idle again: it goes out
    ASSERT_TRUE(run_until([&] { return zero_speed_frames() == 3; }, 5s));
    ASSERT_TRUE(run_until([&] { return core->status().counters.stops_sent == 3; }, 5s));
}

TEST_F(CoreFixture, NewSpeedReplacesAndAngleEndsTheKeepalive) {
    start();
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    ASSERT_TRUE(core->speed(alice, {0, 0, 1000}, 5000ms).ok());
    ASSERT_TRUE(core->speed(bob, {0, 0, -1000}, 5000ms).ok());
    EXPECT_EQ(recorder.motions.back().change, MotionChange::kReplaced);
    EXPECT_EQ(recorder.motions.back().owner->id, bob.id);
    ASSERT_TRUE(core->angle(alice, {0, 0, 4500}).ok());
    // Bob's speed was still waiting behind alice's: the angle replaced it.
    ASSERT_TRUE(run_until([&] { return frames_with("0x85") >= 2; }));
    EXPECT_EQ(trace_of("0x85").back().value("mode", ""), "angle");
    const auto before = speed_frames().size();
    run_for(400ms);
    EXPECT_EQ(speed_frames().size(), before);
    const auto motion = core->status().motion;  // no speed motion; the angle's, tracked
    EXPECT_TRUE(!motion || motion->mode == daemon::MotionMode::kAngle);
    ASSERT_TRUE(core->center(alice).ok());
    ASSERT_TRUE(core->lock(alice).ok());
    ASSERT_TRUE(core->photo(alice).ok());
    ASSERT_TRUE(core->record(alice, {}).ok());
    ASSERT_TRUE(run_until([&] { return frames_with("0x86") == 2; }));
    ASSERT_TRUE(run_until([&] { return simulator->model().state().photos == 1; }));
}

// The recording state is assumed: the gimbal never reports it.
TEST_F(CoreFixture, RecordingStateIsAssumedFromTheTogglesSent) {
    using daemon::RecordingState;
    start();
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    EXPECT_EQ(core->status().recording, RecordingState::kUnknown);
    // A plain toggle from unknown stays unknown.
    auto r = core->record(alice, {});
    ASSERT_TRUE(r.ok());
    EXPECT_TRUE(r->sent);
    EXPECT_EQ(r->recording, RecordingState::kUnknown);
    // Asking for a state while unknown is refused without force.
    r = core->record(alice, {true, false});
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::kInvalidParams);
    EXPECT_NE(r.error().message.find("force"), std::string::npos);
    r = core->record(alice, {true, true});
    ASSERT_TRUE(r.ok());
    EXPECT_TRUE(r->sent);
    EXPECT_EQ(r->recording, RecordingState::kOn);
    r = core->record(alice, {true, false});
    ASSERT_TRUE(r.ok());
    EXPECT_FALSE(r->sent);
    EXPECT_EQ(r->recording, RecordingState::kOn);
    r = core->record(alice, {false, false});
    ASSERT_TRUE(r.ok());
    EXPECT_TRUE(r->sent);
    EXPECT_EQ(r->recording, RecordingState::kOff);
    r = core->record(alice, {});  // a plain toggle flips a known state
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(r->recording, RecordingState::kOn);
    EXPECT_EQ(core->status().recording, RecordingState::kOn);
    ASSERT_TRUE(run_until([&] { return frames_with("0x86") == 4; }));
    run_for(200ms);
    EXPECT_EQ(frames_with("0x86"), 4U);
    // A client that may not command learns nothing changed and sends nothing.
    ASSERT_TRUE(core->acquire(bob).ok());
    r = core->record(alice, {true, false});
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::kBusy);
}

TEST_F(CoreFixture, RecordingStateIsUnknownAgainWhenTheDeviceReopens) {
    using daemon::RecordingState;
    sim::SimOptions options;
    options.link_path = ::testing::TempDir() + "gport-core-rec-" + std::to_string(::getpid());
    options.faults.vanish_every = 600ms;
    options.faults.vanish_for = 300ms;
    start(options);
    // The device vanishes often: retry until a forced "on" goes out.
    ASSERT_TRUE(run_until([&] { return core->record(alice, {true, true}).ok(); }));
    EXPECT_EQ(core->status().recording, RecordingState::kOn);
    const auto opens = core->status().counters.device_opens;
    ASSERT_TRUE(run_until([&] { return core->status().counters.device_opens > opens; }, 10s));
    EXPECT_EQ(core->status().recording, RecordingState::kUnknown);
}

TEST_F(CoreFixture, DurationAboveTheMaximumIsRefused) {
    start();
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    auto r = core->speed(alice, {0, 0, 100}, 3600000ms);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::kInvalidParams);
    EXPECT_NE(r.error().message.find("duration_ms"), std::string::npos);
    EXPECT_EQ(speed_frames().size(), 0U);
}

TEST_F(CoreFixture, SettingsSetIsReadModifyWriteAndKeepsReservedBytes) {
    start();
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    const auto original = simulator->model().state().settings;
    std::optional<daemon::Outcome<daemon::Settings>> got;
    daemon::SettingsChange change;
    change.dead_zone = 7;
    change.inverted = true;
    core->set_settings(alice, change, [&](daemon::Outcome<daemon::Settings> r) { got = r; });
    ASSERT_TRUE(run_until([&] { return got.has_value(); }));
    ASSERT_TRUE(got->ok()) << got->error().message;
    EXPECT_EQ((*got)->dead_zone, 7);
    EXPECT_TRUE((*got)->inverted);
    EXPECT_EQ((*got)->follow_speed, original.follow_speed);
    const auto now = simulator->model().state().settings;
    EXPECT_EQ(now.reserved_head, original.reserved_head);
    EXPECT_EQ(now.reserved_tail, original.reserved_tail);
    EXPECT_EQ(now.dead_zone, 7);
    EXPECT_EQ(frames_with("0x13"), 2U);  // read, then read back
    EXPECT_EQ(frames_with("0x15"), 1U);
}

TEST_F(CoreFixture, ConcurrentSettingsRequestsAreQueuedNotInterleaved) {
    start();
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    std::vector<int> order;
    for (int i = 0; i < 3; ++i) {
        daemon::SettingsChange change;
        change.follow_speed = static_cast<std::uint8_t>(10 + i);
        core->set_settings(alice, change, [&, i](daemon::Outcome<daemon::Settings> r) {
            ASSERT_TRUE(r.ok());
            EXPECT_EQ(r->follow_speed, 10 + i);
            order.push_back(i);
        });
    }
    ASSERT_TRUE(run_until([&] { return order.size() == 3; }));
    EXPECT_EQ(order, (std::vector<int>{0, 1, 2}));
    // On the wire: read, write, read back — three times, never mixed.
    std::string wire;
    for (const auto& t : trace) {
        const auto cmd = t.value("cmd", "");
        if (cmd == "0x13" || cmd == "0x15") {
            wire += cmd == "0x13" ? 'R' : 'W';
        }
    }
    EXPECT_EQ(wire, "RWRRWRRWR");
}

TEST_F(CoreFixture, LinkDownRefusesCommandsAndNeverHangs) {
    auto cfg = test_config("/nonexistent/gimbal");
    core = std::make_unique<daemon::Core>(io, cfg, quiet_logger());
    core->start();
    run_for(200ms);
    EXPECT_EQ(core->status().link, LinkState::kDown);
    auto r = core->speed(alice, {0, 0, 100}, std::nullopt);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::kLinkDown);
    std::optional<daemon::Outcome<daemon::Settings>> got;
    core->get_settings(alice, [&](daemon::Outcome<daemon::Settings> s) { got = s; });
    ASSERT_TRUE(run_until([&] { return got.has_value(); }));
    EXPECT_EQ(got->error().code, ErrorCode::kLinkDown);
    EXPECT_GE(core->status().counters.device_failures, 2U) << "it keeps retrying";
}

// A device that is open but never answers: settings time out with retries.
TEST_F(CoreFixture, SettingsTimeOutWhenTheGimbalIsSilent) {
    int master = -1;
    int slave = -1;
    char name[256] = {};
    ASSERT_EQ(::openpty(&master, &slave, name, nullptr, nullptr), 0);
    core = std::make_unique<daemon::Core>(io, test_config(name), quiet_logger());
    core->start();
    ASSERT_TRUE(run_until([&] { return core->status().device_open; }));
    EXPECT_EQ(core->status().link, LinkState::kStale);
    std::optional<daemon::Outcome<daemon::Settings>> got;
    core->get_settings(alice, [&](daemon::Outcome<daemon::Settings> s) { got = s; });
    ASSERT_TRUE(run_until([&] { return got.has_value(); }));
    ASSERT_FALSE(got->ok());
    EXPECT_EQ(got->error().code, ErrorCode::kNoAnswer);
    EXPECT_EQ(core->status().counters.settings_timeouts, 2U);  // first try + 1 retry
    // Commands still go out although no attitude arrives.
    EXPECT_TRUE(core->center(alice).ok());
    bool done = false;
    core->shutdown([&] { done = true; });
    ASSERT_TRUE(run_until([&] { return done; }));
    core.reset();
    ::close(master);
    ::close(slave);
}

TEST_F(CoreFixture, StaleWhenTelemetryStopsButCommandsStillGoOut) {
    sim::SimOptions options;
    options.model.stream_rate_hz = 0;  // telemetry switched off
    start(options);
    ASSERT_TRUE(run_until([&] { return core->status().device_open; }));
    run_for(400ms);
    EXPECT_EQ(core->status().link, LinkState::kStale);
    EXPECT_TRUE(core->speed(alice, {0, 0, 500}, 300ms).ok());
    ASSERT_TRUE(run_until([&] { return zero_speed_frames() == 1; }));
}

TEST_F(CoreFixture, ReconnectsAfterTheDeviceVanishesAndReappears) {
    sim::SimOptions options;
    options.link_path = ::testing::TempDir() + "gport-core-vanish-" + std::to_string(::getpid());
    options.faults.vanish_every = 600ms;
    options.faults.vanish_for = 300ms;
    start(options);
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    ASSERT_TRUE(core->speed(alice, {0, 0, 500}, 30000ms).ok());
    ASSERT_TRUE(run_until([&] { return core->status().link == LinkState::kDown; }));
    EXPECT_EQ(recorder.motions.back().reason, EndReason::kLinkDown);
    const auto seen = recorder.attitude.size();
    ASSERT_TRUE(run_until([&] { return link_up() && recorder.attitude.size() > seen + 5; }));
    EXPECT_GE(core->status().counters.device_opens, 2U);
}

TEST_F(CoreFixture, NoisyLineStillDeliversValidFrames) {
    sim::SimOptions options;
    options.faults.noise_bytes_per_s = 2000;
    options.faults.corrupt_fraction = 0.2;
    options.faults.shape = sim::WriteShape::kSplit;
    start(options);
    ASSERT_TRUE(run_until([&] { return recorder.attitude.size() >= 40; }));
    const auto c = core->status().counters;
    EXPECT_GT(c.garbage_bytes, 0U);
    EXPECT_GT(c.crc_errors, 0U);
    // Every frame the simulator sent intact arrived (allow those in flight).
    const auto stats = simulator->stats();
    const auto intact = stats.model.attitude_frames - stats.faults.corrupted_frames;
    EXPECT_GE(c.attitude_frames + 3, intact);
}

TEST_F(CoreFixture, ControlArbitration) {
    start();
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    auto held = core->acquire(alice);
    ASSERT_TRUE(held.ok());
    EXPECT_EQ(held.value()->id, alice.id);
    auto busy = core->speed(bob, {0, 0, 100}, std::nullopt);
    ASSERT_FALSE(busy.ok());
    EXPECT_EQ(busy.error().code, ErrorCode::kBusy);
    EXPECT_NE(busy.error().message.find("1001"), std::string::npos) << "names the holder's pid";
    EXPECT_FALSE(core->acquire(bob).ok());
    EXPECT_FALSE(core->release(bob).ok());
    EXPECT_TRUE(core->speed(alice, {0, 0, 100}, std::nullopt).ok());
    core->client_gone(alice);
    EXPECT_FALSE(core->status().controller.has_value());
    EXPECT_TRUE(core->stop(bob).ok());
}

TEST_F(CoreFixture, ReadOnlyPeersMayNotCommand) {
    start({}, [](config::Config& c) { c.access.control_uids = {4242}; });
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    EXPECT_FALSE(core->may_command(bob));
    auto r = core->center(bob);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::kPermission);
    daemon::ClientInfo listed{3, 77, 4242, 4242, {}};
    EXPECT_TRUE(core->center(listed).ok());
    daemon::ClientInfo root{4, 1, 0, 0, {}};
    EXPECT_TRUE(core->may_command(root));
}

TEST_F(CoreFixture, ShutdownStopsRunningMotion) {
    start();
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    ASSERT_TRUE(core->speed(alice, {1000, 0, 0}, 30000ms).ok());
    bool done = false;
    core->shutdown([&] { done = true; });
    ASSERT_TRUE(run_until([&] { return done; }));
    ASSERT_TRUE(run_until([&] { return zero_speed_frames() == 1; }));
    EXPECT_EQ(recorder.motions.back().reason, EndReason::kShutdown);
    core.reset();
}

}  // namespace
}  // namespace gport::testing
