// gportctl's argument parsing: every subcommand, values, and usage errors.
#include "gport/cli/options.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace gport::cli {
namespace {

using nlohmann::json;
using ::testing::HasSubstr;
using namespace std::chrono_literals;

Invocation parse(std::vector<std::string> args, const char* env = nullptr) {
    auto result = parse_args(args, env);
    if (!result) {
        ADD_FAILURE() << "usage error: " << result.error().message;
        return {};
    }
    return *result;
}

std::string refusal(std::vector<std::string> args) {
    auto result = parse_args(args, nullptr);
    if (!result) {
        return result.error().message;
    }
    ADD_FAILURE() << "accepted";
    return {};
}

TEST(Options, OneMethodPerCommand) {
    const std::pair<const char*, const char*> cases[] = {
        {"status", "status"},
        {"attitude", "attitude"},
        {"stop", "stop"},
        {"center", "center"},
        {"lock", "lock"},
        {"photo", "photo"},
        {"record", "record"},
        {"angle", "angle"},
        {"speed", "speed"},
        {"watch", "subscribe"},
        {"settings", "get_settings"},
        {"limits", "limits"},
    };
    for (const auto& [command, method] : cases) {
        EXPECT_EQ(parse({command}).method, method) << command;
    }
}

TEST(Options, SocketFromOptionThenEnvironmentThenDefault) {
    EXPECT_EQ(parse({"status"}).socket, "/run/gportd.sock");
    EXPECT_EQ(parse({"status"}, "/tmp/env.sock").socket, "/tmp/env.sock");
    EXPECT_EQ(parse({"--socket", "/tmp/a.sock", "status"}, "/tmp/env.sock").socket, "/tmp/a.sock");
    EXPECT_EQ(parse({"status", "--socket=/tmp/b.sock"}).socket, "/tmp/b.sock");
    EXPECT_TRUE(parse({"status", "--json"}).json);
}

TEST(Options, SpeedAndAngleTakeDegrees) {
    auto speed = parse({"speed", "--yaw", "-12.5", "--pitch=3", "--for", "1.5s"});
    EXPECT_EQ(speed.params, json({{"yaw", -12.5}, {"pitch", 3.0}, {"duration_ms", 1500}}));
    EXPECT_EQ(speed.duration, 1500ms);
    EXPECT_FALSE(parse({"speed", "--roll", "1"}).duration);
    EXPECT_EQ(parse({"angle", "--pitch", "-90"}).params, json({{"pitch", -90.0}}));
    EXPECT_THAT(refusal({"speed", "--yaw", "400"}), HasSubstr("-327.67 to 327.67"));
    EXPECT_THAT(refusal({"speed", "--yaw", "fast"}), HasSubstr("--yaw: fast: expected deg/s"));
    EXPECT_THAT(refusal({"speed", "--for", "2 hours"}),
                HasSubstr("--for: 2 hours: expected a duration from 1ms to 24h"));
    EXPECT_THAT(refusal({"angle", "--for", "2s"}), HasSubstr("unknown option --for"));
    EXPECT_THAT(refusal({"speed", "--yaw"}), HasSubstr("--yaw needs a value"));
}

TEST(Options, WaitClampAndLease) {
    auto angle = parse({"angle", "--pitch", "-90", "--clamp", "--wait"});
    EXPECT_EQ(angle.params, json({{"pitch", -90.0}, {"clamp", true}, {"wait", true}}));
    EXPECT_TRUE(angle.wait);
    EXPECT_FALSE(parse({"angle", "--pitch", "10"}).wait);
    auto centre = parse({"center", "--wait"});
    EXPECT_EQ(centre.params, json({{"wait", true}}));
    EXPECT_TRUE(centre.wait);
    EXPECT_EQ(parse({"speed", "--yaw", "5", "--lease", "250", "--clamp"}).params,
              json({{"yaw", 5.0}, {"lease_ms", 250}, {"clamp", true}}));
    EXPECT_EQ(parse({"speed", "--lease=2s"}).params, json({{"lease_ms", 2000}}));
    EXPECT_THAT(refusal({"speed", "--lease", "soon"}), HasSubstr("--lease: soon: expected"));
    EXPECT_THAT(refusal({"speed", "--lease", "0"}), HasSubstr("--lease: 0: expected"));
    EXPECT_THAT(refusal({"speed", "--wait"}), HasSubstr("speed: unknown option --wait"));
    EXPECT_THAT(refusal({"center", "--clamp"}), HasSubstr("center: unknown option --clamp"));
    EXPECT_THAT(refusal({"lock", "--wait"}), HasSubstr("lock: unknown option --wait"));
}

TEST(Options, RecordTogglesOrTakesOnOffAndForce) {
    EXPECT_EQ(parse({"record"}).params, json::object());
    EXPECT_EQ(parse({"record", "on"}).params, json({{"on", true}}));
    EXPECT_EQ(parse({"record", "off"}).params, json({{"on", false}}));
    EXPECT_EQ(parse({"record", "on", "--force"}).params, json({{"on", true}, {"force", true}}));
    EXPECT_EQ(parse({"record", "--force", "off"}).params, json({{"on", false}, {"force", true}}));
    EXPECT_THAT(refusal({"record", "maybe"}), HasSubstr("expected on or off"));
    EXPECT_THAT(refusal({"record", "on", "off"}), HasSubstr("unexpected argument \"off\""));
    EXPECT_THAT(refusal({"record", "--force"}), HasSubstr("--force needs on or off"));
    EXPECT_THAT(refusal({"photo", "--force"}), HasSubstr("unknown option --force"));
}

TEST(Options, Durations) {
    EXPECT_EQ(parse_duration("2s"), 2000ms);
    EXPECT_EQ(parse_duration("500ms"), 500ms);
    EXPECT_EQ(parse_duration("0.25s"), 250ms);
    EXPECT_EQ(parse_duration("1m"), 60000ms);
    EXPECT_FALSE(parse_duration("5"));
    EXPECT_FALSE(parse_duration("0ms"));
    EXPECT_FALSE(parse_duration("s"));
    EXPECT_FALSE(parse_duration("-1s"));
    EXPECT_EQ(parse_duration("3h"), 3h);
    EXPECT_FALSE(parse_duration("25h"));  // longer than the protocol's longest (a day)
}

TEST(Options, SettingsGetOrSet) {
    EXPECT_EQ(parse({"settings"}).method, "get_settings");
    auto set = parse({"settings", "--dead-zone", "5", "--inverted", "yes", "--follow-speed", "0"});
    EXPECT_EQ(set.method, "set_settings");
    EXPECT_EQ(set.params, json({{"dead_zone", 5}, {"inverted", true}, {"follow_speed", 0}}));
    EXPECT_THAT(refusal({"settings", "--dead-zone", "256"}), HasSubstr("0 to 255"));
    EXPECT_THAT(refusal({"settings", "--inverted", "maybe"}),
                HasSubstr("--inverted: maybe: expected one of yes, no"));
}

TEST(Options, WatchTopicsAndRate) {
    auto all = parse({"watch"});
    EXPECT_EQ(all.params["topics"], json({"attitude", "link", "motion"}));
    auto some = parse({"watch", "link", "attitude", "--rate", "5"});
    EXPECT_EQ(some.params, json({{"topics", {"link", "attitude"}}, {"max_rate_hz", 5.0}}));
    EXPECT_THAT(refusal({"watch", "weather"}),
                HasSubstr("topics: weather: expected one of attitude, link, motion"));
    EXPECT_THAT(refusal({"watch", "--rate", "0"}), HasSubstr("from 0.01 to 1000"));
    EXPECT_THAT(refusal({"watch", "--rate", "1e-9"}), HasSubstr("from 0.01 to 1000"));
}

TEST(Options, WatchFromSharedMemory) {
    EXPECT_FALSE(parse({"watch"}).shared_memory);
    auto shared = parse({"watch", "attitude", "--shared-memory"});
    EXPECT_TRUE(shared.shared_memory);
    EXPECT_EQ(shared.params, json({{"topics", {"attitude"}}}));
    EXPECT_THAT(refusal({"watch", "--shared-memory", "--rate", "5"}),
                HasSubstr("--rate and --shared-memory cannot be combined"));
}

TEST(Options, HelpAndUsageErrors) {
    EXPECT_TRUE(parse({"--help"}).help);
    EXPECT_THAT(parse({"--help"}).text, HasSubstr("130 interrupted"));
    auto page = parse({"speed", "--help"});
    EXPECT_TRUE(page.help);
    EXPECT_THAT(page.text, HasSubstr("Usage: gportctl speed"));
    EXPECT_THAT(parse({"help", "watch"}).text, HasSubstr("Usage: gportctl watch"));
    EXPECT_THAT(parse({"-h", "angle"}).text, HasSubstr("Usage: gportctl angle"));
    EXPECT_THAT(usage("speed"), HasSubstr("--for DURATION"));
    EXPECT_THAT(usage(""), HasSubstr("acquire and release are not commands"));
    EXPECT_THAT(refusal({"help", "fly"}), HasSubstr("help: unknown command \"fly\""));
    EXPECT_THAT(refusal({}), HasSubstr("no command"));
    EXPECT_THAT(refusal({"fly"}), HasSubstr("unknown command \"fly\""));
    EXPECT_THAT(refusal({"stop", "now"}), HasSubstr("unexpected argument \"now\""));
    EXPECT_THAT(refusal({"status", "--roll", "1"}), HasSubstr("it takes none"));
    EXPECT_EQ(parse({"call", "limits"}).method, "limits");
}

TEST(Options, TyposGetASuggestion) {
    EXPECT_EQ(refusal({"stauts"}), "unknown command \"stauts\"; did you mean \"status\"?");
    EXPECT_EQ(refusal({"atitude"}), "unknown command \"atitude\"; did you mean \"attitude\"?");
    EXPECT_THAT(refusal({"recrod", "on"}), HasSubstr("did you mean \"record\"?"));
    EXPECT_THAT(refusal({"help", "wacth"}), HasSubstr("did you mean \"watch\"?"));
    EXPECT_THAT(refusal({"st"}), ::testing::Not(HasSubstr("did you mean")));  // too short to tell
    EXPECT_THAT(refusal({"xyzzy"}), ::testing::Not(HasSubstr("did you mean")));
    EXPECT_THAT(refusal({"speed", "--yw", "5"}), ::testing::EndsWith("; did you mean --yaw?"));
    EXPECT_THAT(refusal({"angle", "--wiat"}), ::testing::EndsWith("; did you mean --wait?"));
    EXPECT_THAT(refusal({"watch", "--timestamp"}),
                ::testing::EndsWith("did you mean --timestamps?"));
    EXPECT_THAT(refusal({"status", "--jsno"}), ::testing::EndsWith("did you mean --json?"));
    EXPECT_THAT(refusal({"--sokcet", "/x", "status"}), HasSubstr("did you mean --socket?"));
    // A pasted blob is not compared (bounded work), and suggests nothing.
    EXPECT_THAT(refusal({std::string(100000, 's')}), ::testing::Not(HasSubstr("did you mean")));
}

TEST(Options, MisplacedGlobalOptionsAreReportedAsSuch) {
    EXPECT_EQ(refusal({"--bogus", "status"}),
              "unknown option --bogus; the global options are --socket, --json, --help, --version");
    EXPECT_EQ(refusal({"--yaw", "5", "speed"}),
              "--yaw is an option of speed, not a global one: put it after the command "
              "(gportctl speed --yaw ...)");
    EXPECT_THAT(refusal({"--wait", "angle", "--pitch", "1"}),
                HasSubstr("--wait is an option of angle"));
    // After the command, an unknown option is the command's.
    EXPECT_THAT(refusal({"status", "--bogus"}), HasSubstr("status: unknown option --bogus"));
    EXPECT_EQ(parse({"--json", "status"}).json, true);
}

TEST(Options, UsageErrorsNameTheirCommand) {
    auto command_of = [](std::vector<std::string> args) {
        auto result = parse_args(args, nullptr);
        return result ? std::string("(accepted)") : result.error().command;
    };
    EXPECT_EQ(command_of({"speed", "--yaw", "400"}), "speed");
    EXPECT_EQ(command_of({"--socket", "/x", "watch", "-n", "0"}), "watch");
    EXPECT_EQ(command_of({"angle", "--bogus"}), "angle");
    EXPECT_EQ(command_of({"stauts"}), "");
    EXPECT_EQ(command_of({"--bogus", "status"}), "");
}

TEST(Options, CallTakesAMethodAndJsonParams) {
    auto bare = parse({"call", "limits"});
    EXPECT_EQ(bare.command, "call");
    EXPECT_EQ(bare.method, "limits");
    EXPECT_EQ(bare.params, json::object());
    EXPECT_FALSE(bare.raw);
    auto full = parse({"call", "--raw", "subscribe", R"({"topics": ["link"]})"});
    EXPECT_EQ(full.method, "subscribe");
    EXPECT_EQ(full.params, json({{"topics", {"link"}}}));
    EXPECT_TRUE(full.raw);
    EXPECT_EQ(parse({"call", "speed", "[1, 2]"}).params, json({1, 2}));
    EXPECT_THAT(refusal({"call"}), HasSubstr("call: no METHOD given"));
    EXPECT_THAT(refusal({"call", "a b"}),
                HasSubstr("call: METHOD \"a b\": expected a method name"));
    EXPECT_THAT(refusal({"call", "x", "{"}), HasSubstr("PARAMS-JSON is not valid JSON"));
    EXPECT_THAT(refusal({"call", "x", "42"}),
                HasSubstr("PARAMS-JSON is a number: expected a JSON object or array"));
    EXPECT_THAT(refusal({"call", "x", "{}", "more"}), HasSubstr("unexpected argument \"more\""));
    EXPECT_EQ(parse({"limits"}).method, "limits");
}

TEST(Options, WatchTimestamps) {
    EXPECT_TRUE(parse({"watch", "--timestamps"}).timestamps);
    EXPECT_FALSE(parse({"watch"}).timestamps);
    EXPECT_THAT(refusal({"--json", "watch", "--timestamps"}),
                HasSubstr("--timestamps and --json cannot be combined"));
}

TEST(Options, HelpOfACommand) {
    const auto angle = usage("angle");
    EXPECT_THAT(
        angle, HasSubstr("--clamp                     clamp the target into gportd's soft limits"));
    EXPECT_THAT(usage("speed"), HasSubstr("slow to gportd's limits.max_speed instead of refusing"));
    EXPECT_THAT(angle, ::testing::Not(HasSubstr("slow or clamp")));
    // The global options, not the whole exit-status list.
    EXPECT_THAT(angle,
                HasSubstr("Global options (before or after the command): --socket PATH, --json"));
    EXPECT_THAT(angle, ::testing::Not(HasSubstr("130 interrupted")));
    EXPECT_THAT(usage("status"), HasSubstr("Global options"));
    // The overview: usage first, then the note on acquire and the exit statuses.
    const auto overview = usage("");
    EXPECT_LT(overview.find("Usage: gportctl"), overview.find("acquire and release"));
    EXPECT_LT(overview.find("acquire and release"), overview.find("130 interrupted"));
}

TEST(Options, VersionEverywhere) {
    for (const auto& args : {std::vector<std::string>{"--version"}, {"status", "--version"}}) {
        auto version = parse(args);
        EXPECT_TRUE(version.help);
        EXPECT_THAT(version.text, ::testing::StartsWith("gportctl "));
    }
}

TEST(Options, SignedValuesAndUnknownOptionsSwallowNothing) {
    EXPECT_EQ(parse({"speed", "--yaw", "+30"}).params, json({{"yaw", 30.0}}));
    EXPECT_EQ(parse({"angle", "--roll=+1.5", "--pitch", "-2"}).params,
              json({{"roll", 1.5}, {"pitch", -2.0}}));
    EXPECT_THAT(refusal({"status", "--verbose"}), HasSubstr("status: unknown option --verbose"));
    EXPECT_THAT(refusal({"status", "--verbose", "attitude"}), HasSubstr("--verbose"));
    EXPECT_THAT(refusal({"speed", "--yaw", "1", "--x", "2"}),
                HasSubstr("unknown option --x; options: --roll, --pitch, --yaw"));
    EXPECT_THAT(refusal({"--socket"}), HasSubstr("--socket needs a value"));
    EXPECT_THAT(refusal({"speed", "--yaw", "nan"}), HasSubstr("--yaw: nan"));
    EXPECT_THAT(refusal({"angle", "--yaw", "inf"}), HasSubstr("-327.67 to 327.67"));
}

TEST(Options, WatchCountAndDuration) {
    auto counted = parse({"watch", "attitude", "-n", "5"});
    EXPECT_EQ(counted.count, 5);
    EXPECT_FALSE(counted.duration);
    EXPECT_EQ(parse({"watch", "--count=2"}).count, 2);
    EXPECT_EQ(parse({"watch", "--for", "3s"}).duration, 3000ms);
    EXPECT_THAT(refusal({"watch", "-n", "0"}), HasSubstr("--count: 0: expected an integer"));
    EXPECT_THAT(refusal({"watch", "--for", "forever"}), HasSubstr("--for: forever"));
}

TEST(Options, ForIsCheckedAgainstTheProtocolsLongest) {
    EXPECT_EQ(parse({"speed", "--for", "24h"}).duration, 86'400'000ms);
    EXPECT_THAT(refusal({"speed", "--for", "25h"}),
                HasSubstr("--for: 25h: expected a duration from 1ms to 24h"));
    EXPECT_THAT(refusal({"speed", "--lease", "86400001"}), HasSubstr("--lease: 86400001"));
}

// gportctl monitor: its options become the MonitorOptions of run_monitor.
TEST(Options, Monitor) {
    auto inv = parse(
        {"--socket", "/tmp/g.sock", "monitor", "--control", "--for", "3s", "--color", "never"});
    EXPECT_EQ(inv.command, "monitor");
    EXPECT_EQ(inv.monitor.socket, "/tmp/g.sock");
    EXPECT_TRUE(inv.monitor.control);
    EXPECT_EQ(inv.monitor.duration, 3s);
    EXPECT_EQ(inv.monitor.color, ColorMode::kNever);
    auto plain = parse({"monitor"}, "/run/other.sock");
    EXPECT_EQ(plain.monitor.socket, "/run/other.sock");
    EXPECT_FALSE(plain.monitor.control);
    EXPECT_FALSE(plain.monitor.duration);
    EXPECT_EQ(plain.monitor.color, ColorMode::kAuto);
    EXPECT_FALSE(plain.monitor.ascii);
    EXPECT_TRUE(parse({"monitor", "--ascii"}).monitor.ascii);
    EXPECT_THAT(refusal({"monitor", "--for", "soon"}), HasSubstr("--for: soon"));
    EXPECT_THAT(refusal({"monitor", "--color", "pink"}), HasSubstr("--color: pink"));
    EXPECT_THAT(refusal({"monitor", "--yaw", "1"}), HasSubstr("unknown option --yaw"));
}

}  // namespace
}  // namespace gport::cli
