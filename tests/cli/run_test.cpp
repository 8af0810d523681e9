// Whole gportctl runs (in-process, through main_with) against the IPC server
// with a fake core.
#include "gport/cli/run.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <future>
#include <sstream>

#include "server_harness.hpp"

namespace gport::cli {
namespace {

using nlohmann::json;
using ::testing::HasSubstr;
using testing::ServerHarness;

struct Ran {
    int status;
    std::string out;
    std::string err;
};

class RunTest : public ::testing::Test {
  protected:
    Ran run(
        std::vector<std::string> args, std::function<bool()> interrupted = [] { return false; },
        bool tty = false) {
        args.insert(args.begin(), {"--socket", h_.path()});
        out_.str("");
        std::ostringstream err;
        const int status = main_with(args, nullptr, out_, err, std::move(interrupted), tty);
        return {status, out_.str(), err.str()};
    }

    // What gportctl printed so far (the interrupted callback runs on its thread).
    bool printed(std::string_view text) const { return out_.str().find(text) != std::string::npos; }

    std::vector<std::string> calls() {
        return h_.on_io([&] { return h_.api.calls; });
    }

    ServerHarness h_;
    std::ostringstream out_;
};

TEST_F(RunTest, StatusForPeopleAndForScripts) {
    h_.on_io([&] {
        h_.api.status_value.link = daemon::LinkState::kUp;
        h_.api.status_value.device = "/dev/gimbal";
    });
    auto human = run({"status"});
    EXPECT_EQ(human.status, kExitOk) << human.err;
    EXPECT_THAT(human.out, HasSubstr("link:      up"));
    EXPECT_THAT(human.out, HasSubstr("/dev/gimbal"));
    auto script = run({"--json", "status"});
    ASSERT_EQ(script.status, kExitOk);
    EXPECT_EQ(json::parse(script.out)["clients"], 1);
    EXPECT_TRUE(json::parse(script.out)["device_error"].is_null());
}

TEST_F(RunTest, StatusSaysWhyTheDeviceIsClosed) {
    h_.on_io([&] {
        h_.api.status_value.device = "/dev/gimbal";
        h_.api.status_value.device_error = "No such file or directory";
    });
    EXPECT_THAT(run({"status"}).out,
                HasSubstr("device:    /dev/gimbal (closed: No such file or directory)"));
}

TEST_F(RunTest, CommandsReachTheCore) {
    for (const auto* command : {"stop", "center", "lock", "photo"}) {
        auto ran = run({command});
        EXPECT_EQ(ran.status, kExitOk) << command;
        EXPECT_EQ(ran.out, std::string(command) + ": sent\n");
    }
    EXPECT_EQ(run({"record"}).out, "record: sent; recording unknown (assumed)\n");
    EXPECT_EQ(run({"angle", "--pitch", "-45.5"}).status, kExitOk);
    EXPECT_THAT(calls().back(), HasSubstr("angle 0 -4550 0"));
}

// --wait: gportctl blocks until the (fake) core ends the motion.
TEST_F(RunTest, WaitPrintsHowTheMotionEndedAndExitsByIt) {
    const auto wait_for = [&](std::vector<std::string> args, daemon::MotionEnd end) {
        auto ran = std::async(std::launch::async, [&, args] { return run(args); });
        EXPECT_TRUE(h_.eventually([&] { return h_.api.waiters.size() == 1; }));
        h_.on_io([&] {
            h_.api.end_waiter(end);
            return 0;
        });
        return ran.get();
    };
    daemon::AttitudeSample at;
    at.attitude.hall = {0, -4550, 0};
    at.received = std::chrono::steady_clock::now();
    auto reached = wait_for({"angle", "--pitch", "-45.5", "--wait"},
                            {daemon::EndReason::kReached, at, daemon::Millis(800)});
    EXPECT_EQ(reached.status, kExitOk) << reached.err;
    EXPECT_THAT(reached.out, HasSubstr("ended: reached after 800 ms; hall roll 0.00 pitch -45.50"));
    EXPECT_THAT(calls().back(), HasSubstr("angle 0 -4550 0 wait"));
    auto timeout = wait_for({"center", "--wait"},
                            {daemon::EndReason::kTimeout, std::nullopt, daemon::Millis(10000)});
    EXPECT_EQ(timeout.status, kExitNotReached);
    EXPECT_THAT(timeout.out, HasSubstr("ended: timeout after 10000 ms; no attitude received"));
    auto replaced = wait_for({"--json", "angle", "--yaw", "3", "--wait"},
                             {daemon::EndReason::kReplaced, std::nullopt, daemon::Millis(5)});
    EXPECT_EQ(replaced.status, kExitNotReached);
    EXPECT_EQ(json::parse(replaced.out)["ended"]["reason"], "replaced");
}

TEST_F(RunTest, StatusShowsATrackedMotionsTarget) {
    h_.on_io([&] {
        daemon::MotionStatus motion;
        motion.mode = daemon::MotionMode::kAngle;
        motion.target = {0, -3000, 4500};
        motion.elapsed = daemon::Millis(420);
        h_.api.status_value.motion = motion;
    });
    EXPECT_THAT(
        run({"status"}).out,
        HasSubstr("motion:    angle to roll 0.00 pitch -30.00 yaw 45.00 deg, 420 ms so far"));
}

TEST_F(RunTest, RecordOnOffAndTheAssumedState) {
    h_.on_io([&] {
        h_.api.record_result = {false, daemon::RecordingState::kOn};
        h_.api.status_value.recording = daemon::RecordingState::kOn;
    });
    auto ran = run({"record", "on"});
    EXPECT_EQ(ran.status, kExitOk) << ran.err;
    EXPECT_EQ(ran.out, "record: nothing sent; recording on (assumed)\n");
    EXPECT_THAT(calls().back(), HasSubstr("record on -"));
    EXPECT_EQ(run({"record", "off", "--force"}).status, kExitOk);
    EXPECT_THAT(calls().back(), HasSubstr("record off force"));
    EXPECT_THAT(run({"status"}).out, HasSubstr("recording: on (assumed)"));
}

TEST_F(RunTest, DaemonErrorsExitOneWithTheCode) {
    auto none = run({"attitude"});
    EXPECT_EQ(none.status, kExitError);
    EXPECT_THAT(none.err, HasSubstr("error -32000"));
    h_.on_io([&] {
        h_.api.error =
            daemon::CommandError{daemon::ErrorCode::kBusy, "another client holds control (pid 99)"};
    });
    auto busy = run({"photo"});
    EXPECT_EQ(busy.status, kExitError);
    EXPECT_THAT(busy.err, HasSubstr("error -32003: another client holds control (pid 99)"));
}

TEST_F(RunTest, ADurationOverTheDaemonsLimitIsAUsageErrorNamingTheOption) {
    // The daemon's keepalive.max_duration_ms is known only to it.
    h_.api.max_duration_value = daemon::Millis(60000);
    auto ran = run({"speed", "--yaw", "5", "--for", "2m"});
    EXPECT_EQ(ran.status, kExitUsage);
    EXPECT_THAT(ran.err, HasSubstr("--for: 120000 ms is longer than gportd allows: 1 to 60000 ms "
                                   "(its keepalive.max_duration_ms)"));
    EXPECT_THAT(run({"speed", "--yaw", "5", "--lease", "90s", "--for", "1s"}).err,
                HasSubstr("--lease: 90000 ms is longer than gportd allows: 1 to 60000 ms"));
    // An older gportd's core said it in other words.
    h_.api.max_duration_value = daemon::Millis(86400000);
    h_.on_io([&] {
        h_.api.error = daemon::CommandError{daemon::ErrorCode::kInvalidParams,
                                            "lease_ms = 90000 is out of range; allowed 1 to 60000"};
    });
    EXPECT_THAT(run({"speed", "--yaw", "5", "--lease", "90s", "--for", "1s"}).err,
                HasSubstr("--lease: 90000 ms is longer than gportd allows: 1 to 60000 ms"));
}

TEST_F(RunTest, SettingsGetAndSet) {
    auto got = run({"settings"});
    EXPECT_EQ(got.status, kExitOk);
    EXPECT_THAT(got.out, HasSubstr("dead zone:     10"));
    auto set = run({"--json", "settings", "--inverted", "yes", "--dead-zone", "7"});
    EXPECT_EQ(set.status, kExitOk) << set.err;
    EXPECT_EQ(json::parse(set.out),
              json({{"dead_zone", 7}, {"follow_speed", 20}, {"inverted", true}}));
}

TEST_F(RunTest, WatchPrintsEventsUntilInterrupted) {
    bool published = false;
    std::size_t seen = 0;
    auto ran = run({"watch", "attitude", "link"}, [&] {
        if (!published && printed("watching")) {  // subscribed
            published = true;
            h_.on_io([&] {
                daemon::AttitudeSample sample;
                sample.seq = 77;
                sample.attitude.hall = {0, 0, 4500};
                h_.api.observer->on_attitude(sample);
                h_.api.observer->on_link({daemon::LinkState::kStale, "no attitude for 500 ms"});
            });
            return false;
        }
        return printed("link      stale") || ++seen > 100;
    });
    EXPECT_EQ(ran.status, kExitOk);
    EXPECT_THAT(ran.out, HasSubstr("attitude  seq 77"));
    EXPECT_THAT(ran.out, HasSubstr("yaw 45.00"));
    EXPECT_THAT(ran.out, HasSubstr("link      stale (no attitude for 500 ms)"));
}

TEST_F(RunTest, WatchFromSharedMemoryPrintsWhatTheSocketWould) {
    const auto publish = [&](std::uint64_t seq) {
        h_.on_io([&] {
            daemon::AttitudeSample sample;
            sample.seq = seq;
            sample.attitude.hall = {0, 0, 4500};
            h_.api.observer->on_attitude(sample);
        });
    };
    bool published = false;
    std::size_t seen = 0;
    auto ran = run({"watch", "attitude", "link", "--shared-memory"}, [&] {
        if (!published && printed("watching")) {  // the channel is open
            published = true;
            publish(78);
            h_.on_io([&] {
                h_.api.observer->on_link({daemon::LinkState::kStale, "no attitude for 500 ms"});
            });
            return false;
        }
        return (printed("attitude  seq 78") && printed("link      stale")) || ++seen > 200;
    });
    EXPECT_EQ(ran.status, kExitOk) << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("watching attitude, link"));
    EXPECT_THAT(ran.out, HasSubstr("attitude  seq 78"));
    EXPECT_THAT(ran.out, HasSubstr("yaw 45.00"));
    EXPECT_THAT(ran.out, HasSubstr("link      stale (no attitude for 500 ms)"));
}

TEST_F(RunTest, SpeedWithoutDurationKeepsAliveThenStops) {
    auto ran = run({"speed", "--yaw", "20"}, [&] {
        auto so_far = calls();
        return std::count_if(so_far.begin(), so_far.end(),
                             [](const std::string& c) { return c.rfind("speed", 0) == 0; }) >= 3;
    });
    EXPECT_EQ(ran.status, kExitOk) << ran.err;
    auto all = calls();
    ASSERT_GE(all.size(), 4u);
    EXPECT_THAT(all[0], HasSubstr("speed 0 0 2000 500"));
    EXPECT_THAT(all.back(), HasSubstr("stop"));
    EXPECT_THAT(ran.out, HasSubstr("stopped"));
}

TEST_F(RunTest, SpeedForADurationWaitsForTheMotionToEnd) {
    bool ended = false;
    auto ran = run({"speed", "--roll", "5", "--for", "3s"}, [&] {
        if (!ended && printed("moving for")) {
            ended = true;
            h_.on_io([&] {
                daemon::MotionEvent event;
                event.change = daemon::MotionChange::kEnded;
                event.reason = daemon::EndReason::kDuration;
                h_.api.observer->on_motion(event);
            });
        }
        return false;
    });
    EXPECT_EQ(ran.status, kExitOk) << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("moving for 3000 ms"));
    EXPECT_THAT(calls().back(), HasSubstr("speed 500 0 0 3000"));
}

// Publishes an attitude sample and ends the motion once gportctl has started it.
class SpeedForProgress : public RunTest {
  protected:
    Ran speed_for(bool tty) {
        bool ended = false;
        return run(
            {"speed", "--yaw", "5", "--for", "3s"},
            [&] {
                if (!ended && printed("moving for")) {
                    ended = true;
                    h_.on_io([&] {
                        daemon::AttitudeSample sample;
                        sample.attitude.hall = {0, 0, 1234};
                        h_.api.observer->on_attitude(sample);
                        daemon::MotionEvent event;
                        event.change = daemon::MotionChange::kEnded;
                        event.reason = daemon::EndReason::kDuration;
                        h_.api.observer->on_motion(event);
                    });
                }
                return false;
            },
            tty);
    }
};

TEST_F(SpeedForProgress, PlainLinesThenTheEndReason) {
    auto ran = speed_for(false);
    EXPECT_EQ(ran.status, kExitOk) << ran.err;
    EXPECT_THAT(ran.out, ::testing::StartsWith("moving for 3000 ms\nmoving "));
    EXPECT_THAT(ran.out,
                ::testing::EndsWith(
                    "s of 3.0s  hall roll 0.00 pitch 0.00 yaw 12.34 deg\nended: duration\n"));
    EXPECT_THAT(ran.out, ::testing::Not(HasSubstr("\r")));
}

TEST_F(SpeedForProgress, OneLineUpdatedInPlaceOnATerminal) {
    auto ran = speed_for(true);
    EXPECT_EQ(ran.status, kExitOk) << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("\rmoving "));
    EXPECT_THAT(ran.out, HasSubstr("yaw 12.34 deg\x1b[K\nended: duration\n"));
}

TEST_F(RunTest, WatchEndsAfterCountEventsOrTheDuration) {
    bool published = false;
    auto counted = run({"watch", "link", "-n", "2"}, [&] {
        if (!published && printed("watching")) {
            published = true;
            h_.on_io([&] {
                for (int i = 0; i < 3; ++i) {
                    h_.api.observer->on_link({daemon::LinkState::kStale, "no attitude"});
                }
            });
        }
        return false;
    });
    EXPECT_EQ(counted.status, kExitOk) << counted.err;
    std::size_t lines = 0;
    for (std::size_t at = 0; (at = counted.out.find("link      stale", at)) != std::string::npos;
         ++at) {
        ++lines;
    }
    EXPECT_EQ(lines, 2U) << counted.out;
    auto timed = run({"watch", "link", "--for", "100ms"});
    EXPECT_EQ(timed.status, kExitOk) << timed.err;
}

TEST_F(RunTest, SpeedForStopsWhenInterrupted) {
    auto ran = run({"speed", "--pitch", "5", "--for", "1m"}, [&] { return printed("moving for"); });
    EXPECT_EQ(ran.status, kExitOk);
    EXPECT_THAT(calls().back(), HasSubstr("stop"));
}

TEST_F(RunTest, UnreachableDaemonIs69) {
    std::ostringstream out;
    std::ostringstream err;
    const int status = main_with({"--socket", h_.dir() + "/nobody.sock", "status"}, nullptr, out,
                                 err, [] { return false; });
    EXPECT_EQ(status, kExitUnavailable);
    EXPECT_THAT(err.str(), HasSubstr("cannot connect to"));
}

}  // namespace
}  // namespace gport::cli
