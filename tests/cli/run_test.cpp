// Whole gportctl runs (in-process, through main_with) against the IPC server
// with a fake core.
#include "gport/cli/run.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <future>
#include <sstream>

#include "gport/cli/output.hpp"
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
        Terminals terminals = {}) {
        args.insert(args.begin(), {"--socket", h_.path()});
        out_.str("");
        err_.str("");
        const int status = main_with(args, nullptr, out_, err_, std::move(interrupted), terminals);
        return {status, out_.str(), err_.str()};
    }

    // What gportctl printed so far (the interrupted callback runs on its thread).
    bool printed(std::string_view text) const { return out_.str().find(text) != std::string::npos; }
    // watch subscribed (its header, on a terminal's stderr).
    bool watching() const { return err_.str().find("watching") != std::string::npos; }

    std::vector<std::string> calls() {
        return h_.on_io([&] { return h_.api.calls; });
    }

    ServerHarness h_;
    std::ostringstream out_;
    std::ostringstream err_;
};

// watch as on a terminal: the header on stderr tells the test it subscribed.
constexpr Terminals kOnATerminal{false, true};

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
    for (const auto* command : {"stop", "center", "lock"}) {
        auto ran = run({command});
        EXPECT_EQ(ran.status, kExitOk) << command;
        EXPECT_EQ(ran.out, std::string(command) + ": sent\n");
    }
    // A photo and a record toggle are captures: their index is printed.
    EXPECT_EQ(run({"photo"}).out, "photo: sent, capture 1\n");
    EXPECT_EQ(run({"record"}).out, "record: sent, capture 2; recording unknown (assumed)\n");
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
    auto ran = run(
        {"watch", "attitude", "link"},
        [&] {
            if (!published && watching()) {  // subscribed
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
        },
        kOnATerminal);
    EXPECT_EQ(ran.status, kExitOk);
    EXPECT_EQ(ran.err, "watching attitude, link (Ctrl-C to stop)\n");
    EXPECT_THAT(ran.out, ::testing::StartsWith("attitude  seq 77"));
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
    auto ran = run(
        {"watch", "attitude", "link", "--shared-memory"},
        [&] {
            if (!published && watching()) {  // the channel is open
                published = true;
                publish(78);
                h_.on_io([&] {
                    h_.api.observer->on_link({daemon::LinkState::kStale, "no attitude for 500 ms"});
                });
                return false;
            }
            return (printed("attitude  seq 78") && printed("link      stale")) || ++seen > 200;
        },
        kOnATerminal);
    EXPECT_EQ(ran.status, kExitOk) << ran.err;
    EXPECT_THAT(ran.err, HasSubstr("watching attitude, link"));
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
        return run({"speed", "--yaw", "5", "--for", "3s"},
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
                   {tty, false});
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
    auto counted = run(
        {"watch", "link", "-n", "2"},
        [&] {
            if (!published && watching()) {
                published = true;
                h_.on_io([&] {
                    for (int i = 0; i < 3; ++i) {
                        h_.api.observer->on_link({daemon::LinkState::kStale, "no attitude"});
                    }
                });
            }
            return false;
        },
        kOnATerminal);
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

// gportctl call: any method, the result as one line of JSON; --raw the
// whole response; a refusal as every command's (API wording, exit 1).
TEST_F(RunTest, CallPrintsTheResultAsJson) {
    auto limits = run({"call", "limits"});
    EXPECT_EQ(limits.status, kExitOk) << limits.err;
    EXPECT_EQ(json::parse(limits.out)["braking_margin_deg"], 1.0);
    auto angle = run({"call", "angle", R"({"pitch": -30})"});
    EXPECT_EQ(angle.status, kExitOk) << angle.err;
    EXPECT_EQ(json::parse(angle.out)["sent"], true);
    EXPECT_THAT(calls().back(), HasSubstr("angle 0 -3000 0"));
    auto raw = run({"call", "--raw", "get_settings"});
    EXPECT_EQ(raw.status, kExitOk) << raw.err;
    EXPECT_EQ(json::parse(raw.out)["result"]["dead_zone"], 10);
    EXPECT_TRUE(json::parse(raw.out).contains("id"));
}

TEST_F(RunTest, CallRefusalsAreErrorsAsUsual) {
    auto unknown = run({"call", "fly"});
    EXPECT_EQ(unknown.status, kExitError);
    EXPECT_EQ(unknown.out, "");
    EXPECT_THAT(unknown.err, HasSubstr("gportctl: error -32601: "));
    auto bad = run({"call", "--raw", "angle", R"({"pitch": "down"})"});
    EXPECT_EQ(bad.status, kExitError);
    EXPECT_EQ(json::parse(bad.out)["error"]["code"], -32602);
    EXPECT_THAT(bad.err, HasSubstr("gportctl: error -32602: "));
    // Params no JSON-RPC method takes never leave gportctl.
    const auto before = calls().size();
    for (const auto* params : {"5", "\"x\"", "{", "null"}) {
        auto refused = run({"call", "status", params});
        EXPECT_EQ(refused.status, kExitUsage) << params;
        EXPECT_THAT(refused.err, HasSubstr("PARAMS-JSON")) << params;
        EXPECT_THAT(refused.err, HasSubstr("Try 'gportctl call --help'.")) << params;
    }
    EXPECT_EQ(calls().size(), before);
}

TEST_F(RunTest, CallRefusesADeepOrHugeRequestBeforeSendingIt) {
    const std::string deep = std::string(100, '[') + std::string(100, ']');
    auto refused = run({"call", "status", deep});
    EXPECT_EQ(refused.status, kExitUsage);
    EXPECT_THAT(refused.err, HasSubstr("PARAMS-JSON nests deeper than 32 levels"));
    auto name = run({"call", std::string(10000, 'a')});
    EXPECT_EQ(name.status, kExitUsage);
    EXPECT_THAT(name.err, HasSubstr("expected a method name"));
    EXPECT_EQ(run({"call", "status\n{\"id\":9,\"method\":\"stop\"}"}).status, kExitUsage);
}

TEST_F(RunTest, LimitsForPeople) {
    h_.api.limits_value.pitch = {-90, 30};
    h_.api.limits_value.max_speed = 60;
    auto ran = run({"limits"});
    EXPECT_EQ(ran.status, kExitOk) << ran.err;
    EXPECT_EQ(ran.out,
              "roll:           -327.67 to 327.67 deg (no limit)\n"
              "pitch:          -90 to 30 deg\n"
              "yaw:            -327.67 to 327.67 deg (no limit)\n"
              "max speed:      60 deg/s\n"
              "braking margin: 1 deg\n");
    EXPECT_EQ(json::parse(run({"--json", "limits"}).out)["pitch"]["min"], -90);
}

// Refusals speak of gportctl's options, not of the API's params.
TEST_F(RunTest, RefusalsAreWordedForTheCommandLine) {
    h_.on_io([&] {
        h_.api.error = daemon::CommandError{
            daemon::ErrorCode::kInvalidParams,
            "the recording state is unknown (gportd cannot read it); send record "
            "{\"on\": true, \"force\": true} to toggle anyway and take on as the new state"};
    });
    auto record = run({"record", "on"});
    EXPECT_EQ(record.status, kExitError);
    EXPECT_EQ(record.err,
              "gportctl: error -32602: the recording state is unknown (gportd cannot read it); "
              "run 'gportctl record on --force' to toggle anyway and take on as the new state\n");
    h_.on_io([&] {
        h_.api.error = daemon::CommandError{
            daemon::ErrorCode::kInvalidParams,
            "pitch -120 is beyond -90 to 30 (limits.pitch); clamp: true moves as far as allowed"};
    });
    EXPECT_THAT(run({"angle", "--pitch", "-120"}).err,
                HasSubstr("(limits.pitch); --clamp moves as far as allowed\n"));
    // call speaks the API.
    EXPECT_THAT(run({"call", "angle", R"({"pitch": -120})"}).err,
                HasSubstr("clamp: true moves as far as allowed"));
}

TEST_F(RunTest, WatchSaysWhatItWatchesOnlyOnATerminal) {
    auto piped = run({"watch", "link", "-n", "1", "--for", "50ms"});
    EXPECT_EQ(piped.status, kExitOk) << piped.err;
    EXPECT_EQ(piped.out, "");
    EXPECT_EQ(piped.err, "");
    auto shown = run(
        {"watch", "link", "motion", "--for", "50ms"}, [] { return false; }, kOnATerminal);
    EXPECT_EQ(shown.out, "");
    EXPECT_EQ(shown.err, "watching link, motion (Ctrl-C to stop)\n");
}

TEST_F(RunTest, WatchTimestampsEachLine) {
    bool published = false;
    auto ran = run(
        {"watch", "link", "--timestamps", "-n", "2"},
        [&] {
            if (!published && watching()) {
                published = true;
                h_.on_io([&] {
                    h_.api.observer->on_link({daemon::LinkState::kStale, "no attitude"});
                    h_.api.observer->on_link({daemon::LinkState::kUp, "attitude again"});
                });
            }
            return false;
        },
        kOnATerminal);
    EXPECT_EQ(ran.status, kExitOk) << ran.err;
    EXPECT_THAT(ran.out, ::testing::MatchesRegex(
                             "([0-9]{4}-[0-9]{2}-[0-9]{2}T[0-9]{2}:[0-9]{2}:[0-9]{2}\\.[0-9]{3}"
                             "[+-][0-9]{2}:[0-9]{2} link      [a-z]+ \\([a-z ]+\\)\n){2}"));
}

// One format for a daemon's refusal, whichever way it reached gportctl.
TEST_F(RunTest, OneErrorFormat) {
    EXPECT_EQ(
        format_error(client::Error(-32003, "another client holds control (pid 7)")),
        format_error(json{{"code", -32003}, {"message", "another client holds control (pid 7)"}}));
    EXPECT_EQ(format_error(client::Error(-32003, "held")), "error -32003: held");
    EXPECT_EQ(
        format_error(client::Error(client::ErrorCode::kTransport, "cannot connect to /x: gone")),
        "cannot connect to /x: gone");
}

// watch --timestamps: local time, milliseconds, the UTC offset.
TEST(Timestamps, Iso8601LocalTimeWithMilliseconds) {
    const char* saved = std::getenv("TZ");
    const std::string before = saved != nullptr ? saved : "";
    const auto restore = [&] {
        saved != nullptr ? ::setenv("TZ", before.c_str(), 1) : ::unsetenv("TZ");
        ::tzset();
    };
    const auto when =
        std::chrono::system_clock::time_point(std::chrono::milliseconds(1'777'900'927'250));
    ::setenv("TZ", "CEST-2", 1);  // POSIX: 2 hours east of UTC
    ::tzset();
    EXPECT_EQ(format_timestamp(when), "2026-05-04T15:22:07.250+02:00");
    ::setenv("TZ", "NST+3:30", 1);
    ::tzset();
    EXPECT_EQ(format_timestamp(when + std::chrono::milliseconds(5)),
              "2026-05-04T09:52:07.255-03:30");
    restore();
}

// Usage errors point at the help of the command they concern.
TEST_F(RunTest, UsageHintsNameTheCommand) {
    EXPECT_THAT(run({"angle", "--pitch", "400"}).err,
                HasSubstr("\nTry 'gportctl angle --help'.\n"));
    EXPECT_THAT(run({"speed", "--yw", "5"}).err, HasSubstr("\nTry 'gportctl speed --help'.\n"));
    EXPECT_THAT(run({"record", "--force"}).err, HasSubstr("\nTry 'gportctl record --help'.\n"));
    EXPECT_THAT(run({"stauts"}).err, HasSubstr("\nTry 'gportctl --help'.\n"));
    EXPECT_THAT(run({"--bogus", "status"}).err, HasSubstr("\nTry 'gportctl --help'.\n"));
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
