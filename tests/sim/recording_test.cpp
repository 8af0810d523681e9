// The recording format and the command line.
#include "gport/sim/recording.hpp"

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "gport/sim/command_line.hpp"

namespace gport::sim {
namespace {

using namespace std::chrono_literals;

std::string temp_file(const std::string& name) {
    return (std::filesystem::temp_directory_path() / (name + "." + std::to_string(::getpid())))
        .string();
}

TEST(Recording, LinesRoundTrip) {
    const RecordEntry e{1234567us, Direction::kTx, {0xAE, 0x01, 0x00, 0x16, 0x17}};
    EXPECT_EQ(format_record_line(e), "1234567 tx ae01001617");
    const auto back = parse_record_line("1234567 tx ae01001617");
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(*back, e);
}

TEST(Recording, BadLinesSayWhatIsWrong) {
    EXPECT_NE(parse_record_line("12 up ae").error().message.find("direction 'up'"),
              std::string::npos);
    EXPECT_NE(parse_record_line("x rx ae").error().message.find("time 'x'"), std::string::npos);
    EXPECT_NE(parse_record_line("1 rx aez0").error().message.find("hex"), std::string::npos);
    EXPECT_FALSE(parse_record_line("1 rx").ok());
    EXPECT_FALSE(parse_record_line("1 rx ab cd").ok());
}

TEST(Recording, RecorderWritesWhatLoadReads) {
    const auto path = temp_file("gport-sim-rec");
    {
        Recorder r(path);
        r.write(10us, Direction::kRx, std::vector<std::uint8_t>{0x01});
        r.write(20us, Direction::kTx, std::vector<std::uint8_t>{0x02, 0x03});
    }
    const auto loaded = load_recording(path);
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    ASSERT_EQ(loaded->size(), 2U);
    EXPECT_EQ(loaded->at(1), (RecordEntry{20us, Direction::kTx, {0x02, 0x03}}));
    std::ofstream(path, std::ios::app) << "5 tx 00\n";  // goes back in time
    EXPECT_NE(load_recording(path).error().message.find(":4: time goes backwards"),
              std::string::npos);
    std::filesystem::remove(path);
    EXPECT_NE(load_recording(path).error().message.find("cannot open"), std::string::npos);
}

Result<CommandLine, OptionError> parse(std::initializer_list<std::string_view> args) {
    const std::vector<std::string_view> v(args);
    return parse_command_line(v);
}

TEST(CommandLine, ParsesEveryOption) {
    const auto cl =
        parse({"--link",  "/tmp/g",          "--rate=100", "--form",        "24",  "--slew",
               "30",      "--noise",         "10",         "--corrupt-crc", "0.1", "--merge",
               "3",       "--silence-every", "1000",       "--silence-for", "200", "--vanish-every",
               "5000",    "--vanish-for",    "2000",       "--seed",        "7",   "--pace",
               "--trace", "--record",        "/tmp/r"});
    ASSERT_TRUE(cl.ok()) << cl.error().message;
    const auto& o = cl->options;
    EXPECT_EQ(o.link_path, "/tmp/g");
    EXPECT_EQ(o.model.stream_rate_hz, 100);
    EXPECT_EQ(o.model.form, AttitudeForm::kLong24);
    EXPECT_EQ(o.model.slew_deg_s, 30);
    EXPECT_EQ(o.faults.noise_bytes_per_s, 10);
    EXPECT_EQ(o.faults.corrupt_fraction, 0.1);
    EXPECT_EQ(o.faults.shape, WriteShape::kMerge);
    EXPECT_EQ(o.faults.merge_count, 3U);
    EXPECT_EQ(o.faults.silence_for, 200ms);
    EXPECT_EQ(o.faults.vanish_every, 5000ms);
    EXPECT_EQ(o.faults.seed, 7U);
    EXPECT_TRUE(o.pace);
    EXPECT_TRUE(cl->trace);
    EXPECT_EQ(o.record_path, "/tmp/r");
}

TEST(CommandLine, LimitsSetTheMechanicalRange) {
    const auto cl = parse({"--limits", "30,40.5,170"});
    ASSERT_TRUE(cl.ok()) << cl.error().message;
    EXPECT_EQ(cl->options.model.limits, (Vec3{30, 40.5, 170}));
    EXPECT_EQ(parse({})->options.model.limits, (Vec3{45, 90, 170})) << "the documented default";
    for (auto bad : {"30,40", "30,40,50,60", "0,40,50", "30,-1,50", "30,40,181", "30,,50", "a,b,c",
                     "30,40,50,", ""}) {
        const auto refused = parse({"--limits", bad});
        ASSERT_FALSE(refused.ok()) << bad;
        EXPECT_NE(refused.error().message.find(
                      "--limits: needs three mechanical limits ROLL,PITCH,YAW in degrees, each "
                      "above 0 and at most 180"),
                  std::string::npos)
            << refused.error().message;
        EXPECT_NE(refused.error().message.find(fmt::format("got '{}'", bad)), std::string::npos)
            << refused.error().message;
    }
}

TEST(CommandLine, DefaultsAreTheDocumentedOnes) {
    const auto cl = parse({});
    ASSERT_TRUE(cl.ok());
    EXPECT_EQ(cl->options.model.stream_rate_hz, 50);
    EXPECT_EQ(cl->options.model.form, AttitudeForm::kShort12);
    EXPECT_FALSE(cl->options.pace);
    EXPECT_FALSE(cl->trace);
}

TEST(CommandLine, ErrorsNameTheOptionAndWhatIsAllowed) {
    const auto expect_error = [](std::initializer_list<std::string_view> args,
                                 const std::string& needle) {
        const auto cl = parse(args);
        ASSERT_FALSE(cl.ok()) << needle;
        EXPECT_NE(cl.error().message.find(needle), std::string::npos) << cl.error().message;
    };
    expect_error({"--rate", "fast"}, "--rate: fast: expected frames per second from 0 to 10000");
    expect_error({"--rate", "20000"}, "from 0 to 10000");
    expect_error({"--form", "13"}, "12 or 24");
    expect_error({"--corrupt-crc", "2"}, "from 0 to 1");
    expect_error({"--bogus"}, "unknown option --bogus; the options are");
    expect_error({"extra"}, "unexpected argument \"extra\"; gport-sim takes only options");
    expect_error({"--link"}, "--link needs a value");
    expect_error({"--pace=maybe"}, "--pace");
    expect_error({"--vanish-for", "100"}, "must be given together");
    expect_error({"--split", "--merge", "2"}, "cannot be combined");
    expect_error({"--merge", "2.5"}, "--merge: 2.5: expected an integer from 2 to 64");
    expect_error({"--replay", "x", "--noise", "5"}, "cannot be combined with fault injection");
}

TEST(CommandLine, VersionAndTheSharedSyntax) {
    EXPECT_TRUE(parse({"--version"})->version);
    EXPECT_TRUE(parse({"-h"})->help);
    EXPECT_THAT(version_text(), ::testing::MatchesRegex("gport-sim [0-9]+\\.[0-9]+\\.[0-9]+\n"));
    const auto cl = parse({"--rate=+20", "--seed", "4294967295", "--rate", "30"});
    ASSERT_TRUE(cl.ok()) << cl.error().message;
    EXPECT_EQ(cl->options.model.stream_rate_hz, 30);  // the last one wins
    EXPECT_EQ(cl->options.faults.seed, 4294967295U);
}

TEST(CommandLine, HelpMentionsEveryOption) {
    const auto help = help_text();
    for (const char* option :
         {"--link",          "--pace",        "--rate",         "--form",       "--slew",
          "--limits",        "--noise",       "--corrupt-crc",  "--split",      "--merge",
          "--silence-every", "--silence-for", "--vanish-every", "--vanish-for", "--seed",
          "--trace",         "--record",      "--replay",       "--help",       "Examples"}) {
        EXPECT_NE(help.find(option), std::string::npos) << option;
    }
}

}  // namespace
}  // namespace gport::sim
