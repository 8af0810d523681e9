// The command line: each option, both value forms, and every usage error.
#include <gtest/gtest.h>

#include <initializer_list>
#include <vector>

#include "test_support.hpp"

namespace gport::config::test {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

Result<CommandLine> parse(std::initializer_list<const char*> options) {
    std::vector<const char*> argv{"gportd"};
    argv.insert(argv.end(), options);
    return parse_command_line(argv);
}

TEST(CommandLine, NoOptionsLeavesEverythingUnset) {
    auto c = parse({});
    ASSERT_TRUE(c.ok()) << c.error().text();
    EXPECT_FALSE(c->config_path || c->device || c->socket_path || c->log_level);
    EXPECT_FALSE(c->simulate || c->help || c->version);
}

TEST(CommandLine, ProbeWithAndWithoutDevices) {
    auto none = parse({"--probe"});
    ASSERT_TRUE(none.ok()) << none.error().text();
    ASSERT_TRUE(none->probe.has_value());
    EXPECT_TRUE(none->probe->empty()) << "no devices: the usual ones";
    auto some = parse({"--probe", "/dev/ttyUSB0", "/dev/serial0"});
    ASSERT_TRUE(some.ok()) << some.error().text();
    ASSERT_TRUE(some->probe.has_value());
    EXPECT_EQ(*some->probe, (std::vector<std::string>{"/dev/ttyUSB0", "/dev/serial0"}));
    EXPECT_FALSE(parse({})->probe.has_value());
}

TEST(CommandLine, EveryOptionWithSeparateValues) {
    auto c = parse({"--config", "/tmp/g.json", "--device", "/dev/ttyUSB1", "--socket",
                    "/tmp/g.sock", "--log-level", "debug", "--simulate"});
    ASSERT_TRUE(c.ok()) << c.error().text();
    EXPECT_EQ(c->config_path, "/tmp/g.json");
    EXPECT_EQ(c->device, "/dev/ttyUSB1");
    EXPECT_EQ(c->socket_path, "/tmp/g.sock");
    EXPECT_EQ(c->log_level, "debug");
    EXPECT_TRUE(c->simulate);
}

TEST(CommandLine, EveryOptionWithEqualsForm) {
    auto c = parse({"--config=/tmp/g.json", "--device=/dev/ttyUSB1", "--socket=/tmp/a=b.sock",
                    "--log-level=warn"});
    ASSERT_TRUE(c.ok()) << c.error().text();
    EXPECT_EQ(c->config_path, "/tmp/g.json");
    EXPECT_EQ(c->device, "/dev/ttyUSB1");
    EXPECT_EQ(c->socket_path, "/tmp/a=b.sock");  // only the first '=' separates
    EXPECT_EQ(c->log_level, "warn");
}

TEST(CommandLine, HelpAndVersionFlags) {
    EXPECT_TRUE(parse({"--help"})->help);
    EXPECT_TRUE(parse({"-h"})->help);
    EXPECT_TRUE(parse({"--version"})->version);
}

TEST(CommandLine, TheLastOfARepeatedOptionWins) {
    auto c = parse({"--device", "/dev/a", "--device=/dev/b"});
    ASSERT_TRUE(c.ok()) << c.error().text();
    EXPECT_EQ(c->device, "/dev/b");
}

TEST(CommandLine, MissingValueAtTheEndOrBeforeAnotherOption) {
    EXPECT_THAT(parse({"--config"}).error().messages, ElementsAre("--config needs a value"));
    // As in gportctl and gport-sim: the next argument is the value, checked as one.
    EXPECT_THAT(parse({"--device", "--simulate"}).error().messages,
                ElementsAre(HasSubstr("--device: must be an absolute path")));
}

TEST(CommandLine, EmptyValuesAreRefused) {
    EXPECT_THAT(parse({"--config="}).error().messages, ElementsAre("--config needs a value"));
    EXPECT_THAT(parse({"--config", ""}).error().messages,
                ElementsAre(HasSubstr("--config: must name a file")));
    EXPECT_THAT(parse({"--socket", ""}).error().messages,
                ElementsAre(HasSubstr("--socket: must be an absolute path")));
}

TEST(CommandLine, UnknownOptionListsTheOptions) {
    EXPECT_THAT(
        parse({"--verbose"}).error().messages,
        ElementsAre("unknown option --verbose; the options are --help, --version, "
                    "--config, --device, --socket, --log-level, --state-dir, --simulate, --probe"));
    EXPECT_THAT(parse({"--devices=/dev/x"}).error().messages,
                ElementsAre(HasSubstr("unknown option --devices;")));
}

TEST(CommandLine, PositionalArgumentsAreRefused) {
    EXPECT_THAT(parse({"/dev/ttyUSB0"}).error().messages,
                ElementsAre("unexpected argument \"/dev/ttyUSB0\"; gportd takes only options"));
}

TEST(CommandLine, FlagsTakeOnlyABooleanValue) {
    EXPECT_TRUE(parse({"--simulate=yes"})->simulate);
    EXPECT_FALSE(parse({"--simulate=false"})->simulate);
    EXPECT_THAT(parse({"--simulate=maybe"}).error().messages, ElementsAre(HasSubstr("--simulate")));
}

TEST(CommandLine, ValuesAreCheckedLikeTheFile) {
    EXPECT_THAT(parse({"--log-level", "loud"}).error().messages,
                ElementsAre(ErrorWith("--log-level: must be one of trace, debug", "got \"loud\"")));
    EXPECT_THAT(parse({"--device=ttyUSB0"}).error().messages,
                ElementsAre(ErrorWith("--device: must be an absolute path")));
    EXPECT_THAT(parse({"--socket", ("/" + std::string(200, 's')).c_str()}).error().messages,
                ElementsAre(ErrorWith("--socket: must be at most 107 bytes")));
}

TEST(CommandLine, TheFirstUsageErrorIsReported) {
    auto c = parse({"--log-level=loud", "--bogus", "extra"});
    EXPECT_THAT(c.error().messages, ElementsAre(HasSubstr("--log-level")));
}

TEST(CommandLine, SignedAndDashValuesAreTheSameAsInTheOtherPrograms) {
    auto c = parse({"--config", "-relative.json"});
    ASSERT_TRUE(c.ok()) << c.error().text();
    EXPECT_EQ(c->config_path, "-relative.json");
}

TEST(CommandLine, UsageNamesEveryOptionAndTheExitStatuses) {
    const auto text = usage();
    for (const char* piece :
         {"--config FILE", "--device PATH", "--socket PATH", "--log-level LEVEL", "--simulate",
          "--help", "--version", "/etc/gportd/gportd.json", "64", "78"}) {
        EXPECT_THAT(text, HasSubstr(piece));
    }
    EXPECT_EQ(text.back(), '\n');
}

TEST(CommandLine, VersionText) {
    EXPECT_THAT(version_text(), testing::MatchesRegex("gportd [0-9]+\\.[0-9]+\\.[0-9]+\n"));
}

TEST(CommandLine, ExitStatusesFollowSysexits) {
    EXPECT_EQ(kExitUsage, 64);
    EXPECT_EQ(kExitConfig, 78);
}

}  // namespace
}  // namespace gport::config::test
