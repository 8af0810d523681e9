// gport-mavlink's options: command line over config over defaults; bad
// options exit 64, a bad config 78 (docs/mavlink.md, "Options").
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "gport/mavlink/bridge/options.hpp"

namespace gport::mavlink::bridge {
namespace {

ParseOutcome parse(std::vector<std::string> args, const std::string& env = "",
                   const std::string& state_directory = "") {
    args.insert(args.begin(), "gport-mavlink");
    return parse_options(args, {env, state_directory});
}

std::string write_config(const std::string& text) {
    const auto path = std::filesystem::temp_directory_path() /
                      ("gport-mavlink-test-" + std::to_string(::getpid()) + ".json");
    std::ofstream(path) << text;
    return path.string();
}

TEST(Options, Defaults) {
    const auto out = parse({});
    ASSERT_TRUE(out.options) << out.text;
    EXPECT_EQ(out.options->socket, "/run/gportd.sock");
    EXPECT_EQ(to_string(out.options->mavlink), "udpin:127.0.0.1:14560");  // loopback only
    EXPECT_EQ(out.options->sysid, 1);
    EXPECT_EQ(out.options->gcs_sysids, std::vector<std::uint8_t>{255});
    EXPECT_TRUE(out.options->signing_key.empty());
    EXPECT_TRUE(out.options->state_dir.empty());
    EXPECT_EQ(out.options->compid, 154);
    EXPECT_EQ(out.options->attitude_rate_hz, 10);
    EXPECT_EQ(out.options->lease_ms, 500U);
}

// config/mavlink.json, installed as the example (docs/mavlink.md): every key
// at its default, so copying it to /etc/gportd/mavlink.json changes nothing
// until edited.
TEST(Options, TheShippedExampleHoldsTheDefaults) {
    const auto defaults = parse({});
    const auto example = parse({"--config", GPORT_MAVLINK_EXAMPLE});
    ASSERT_TRUE(defaults.options && example.options) << example.text;
    EXPECT_EQ(example.options->socket, defaults.options->socket);
    EXPECT_EQ(to_string(example.options->mavlink), to_string(defaults.options->mavlink));
    EXPECT_EQ(example.options->sysid, defaults.options->sysid);
    EXPECT_EQ(example.options->gcs_sysids, defaults.options->gcs_sysids);
    EXPECT_EQ(example.options->compid, defaults.options->compid);
    EXPECT_EQ(example.options->camera, defaults.options->camera);
    EXPECT_EQ(example.options->attitude_rate_hz, defaults.options->attitude_rate_hz);
    EXPECT_EQ(example.options->lease_ms, defaults.options->lease_ms);
}

TEST(Options, EnvironmentSocketAndCommandLine) {
    const auto out = parse({"--mavlink", "udpout:127.0.0.1:14555", "--sysid", "3", "--compid",
                            "155", "--attitude-rate", "20", "--lease-ms", "300", "--invert-yaw"},
                           "/tmp/g.sock");
    ASSERT_TRUE(out.options) << out.text;
    EXPECT_EQ(out.options->socket, "/tmp/g.sock");
    EXPECT_EQ(out.options->mavlink.kind, Endpoint::Kind::kUdpOut);
    EXPECT_EQ(out.options->mavlink.number, 14555U);
    EXPECT_EQ(out.options->sysid, 3);
    EXPECT_EQ(out.options->compid, 155);
    EXPECT_EQ(out.options->attitude_rate_hz, 20);
    EXPECT_EQ(out.options->lease_ms, 300U);
    EXPECT_TRUE(out.options->invert.yaw);
    EXPECT_FALSE(out.options->invert.roll);
}

TEST(Options, Endpoints) {
    std::string error;
    auto serial = parse_endpoint("serial:/dev/ttyAMA0:921600", error);
    ASSERT_TRUE(serial) << error;
    EXPECT_EQ(serial->kind, Endpoint::Kind::kSerial);
    EXPECT_EQ(serial->address, "/dev/ttyAMA0");
    EXPECT_EQ(serial->number, 921600U);
    EXPECT_FALSE(parse_endpoint("tcp:1.2.3.4:5", error));
    EXPECT_NE(error.find("udpin:ADDR:PORT"), std::string::npos);
    EXPECT_FALSE(parse_endpoint("udpin:0.0.0.0:70000", error));
    EXPECT_NE(error.find("1 to 65535"), std::string::npos);
    EXPECT_FALSE(parse_endpoint("udpin", error));
}

TEST(Options, BadOptionsExit64) {
    EXPECT_EQ(parse({"--sysid", "0"}).exit_code, 64);
    EXPECT_EQ(parse({"--sysid", "automatic"}).exit_code, 64);
    EXPECT_EQ(parse({"--gcs-sysid", "255,0"}).exit_code, 64);
    EXPECT_EQ(parse({"--gcs-sysid", ""}).exit_code, 64);
    EXPECT_EQ(parse({"--signing-key", ""}).exit_code, 64);
    EXPECT_EQ(parse({"--mavlink", "tcp:x:1"}).exit_code, 64);
    EXPECT_EQ(parse({"--attitude-rate", "0"}).exit_code, 64);
    EXPECT_EQ(parse({"--lease-ms", "10"}).exit_code, 64);
    EXPECT_EQ(parse({"--log-level", "loud"}).exit_code, 64);
    EXPECT_EQ(parse({"--bogus"}).exit_code, 64);
}

TEST(Options, OutOfRangeNamesOptionValueAndWhatIsAllowed) {
    const auto out = parse({"--sysid", "300"});
    EXPECT_FALSE(out.options);
    EXPECT_EQ(out.exit_code, 64);
    EXPECT_NE(out.text.find("--sysid: 300: expected a system id from 1 to 255, or auto"),
              std::string::npos)
        << out.text;
    EXPECT_NE(parse({"--gcs-sysid", "255,x"})
                  .text.find("--gcs-sysid: 255,x: \"x\" is not a system id; expected system ids "
                             "from 1 to 255 separated by commas (255,250), or none"),
              std::string::npos);
    EXPECT_NE(parse({"--attitude-rate", "0"})
                  .text.find("--attitude-rate: 0: expected messages per second from 0.1 to 100"),
              std::string::npos);
    EXPECT_NE(parse({"--log-level", "loud"})
                  .text.find("--log-level: loud: expected one of trace, debug, info, warn, "
                             "error, critical, off"),
              std::string::npos);
}

TEST(Options, UnknownOptionAndStrayArgumentAreNamed) {
    const auto unknown = parse({"--bogus=1"});
    EXPECT_EQ(unknown.exit_code, 64);
    EXPECT_NE(unknown.text.find("unknown option --bogus; the options are"), std::string::npos)
        << unknown.text;
    const auto stray = parse({"udpin:0.0.0.0:14550"});
    EXPECT_EQ(stray.exit_code, 64);
    EXPECT_NE(stray.text.find("unexpected argument \"udpin:0.0.0.0:14550\"; gport-mavlink takes "
                              "only options"),
              std::string::npos)
        << stray.text;
    EXPECT_NE(parse({"--sysid"}).text.find("--sysid needs a value"), std::string::npos);
}

TEST(Options, VersionExits0) {
    const auto out = parse({"--version"});
    EXPECT_FALSE(out.options);
    EXPECT_EQ(out.exit_code, 0);
    EXPECT_EQ(out.text.rfind("gport-mavlink ", 0), 0U) << out.text;
}

TEST(Options, HelpExits0) {
    const auto out = parse({"--help"});
    EXPECT_FALSE(out.options);
    EXPECT_EQ(out.exit_code, 0);
    EXPECT_NE(out.text.find("--mavlink URL"), std::string::npos) << out.text;
    EXPECT_NE(out.text.find("print this help and exit"), std::string::npos);
    EXPECT_NE(out.text.find("Exit status:"), std::string::npos);
}

TEST(Options, ConfigSectionUnderTheCommandLine) {
    const auto path = write_config(
        "{\n // comment\n \"mavlink\": {\"url\": \"udpin:127.0.0.1:14600\", \"sysid\": 5,"
        " \"attitude_rate_hz\": 5, \"invert\": {\"pitch\": true}}}");
    const auto out = parse({"--config", path, "--attitude-rate", "25"});
    ASSERT_TRUE(out.options) << out.text;
    EXPECT_EQ(out.options->mavlink.number, 14600U);
    EXPECT_EQ(out.options->sysid, 5);
    EXPECT_EQ(out.options->attitude_rate_hz, 25);
    EXPECT_TRUE(out.options->invert.pitch);
    std::filesystem::remove(path);
}

TEST(Options, SysidAutoAndGroundStationLists) {
    auto out = parse({"--sysid", "auto", "--gcs-sysid", "255,250,7"});
    ASSERT_TRUE(out.options) << out.text;
    EXPECT_FALSE(out.options->sysid);
    EXPECT_EQ(out.options->gcs_sysids, (std::vector<std::uint8_t>{255, 250, 7}));
    out = parse({"--gcs-sysid", "none", "--sysid", "42"});
    ASSERT_TRUE(out.options) << out.text;
    EXPECT_TRUE(out.options->gcs_sysids.empty());
    EXPECT_EQ(out.options->sysid, 42);
    EXPECT_EQ(to_string(std::vector<std::uint8_t>{}), "none");
    EXPECT_EQ(to_string(std::vector<std::uint8_t>{255, 7}), "255,7");
}

TEST(Options, ASigningKeyNeedsAStateDirectory) {
    const auto alone = parse({"--signing-key", "/etc/gportd/mavlink.key"});
    EXPECT_FALSE(alone.options);
    EXPECT_EQ(alone.exit_code, 64);
    EXPECT_NE(alone.text.find("needs a state directory"), std::string::npos) << alone.text;
    EXPECT_NE(alone.text.find("--state-dir"), std::string::npos);
    const auto given = parse({"--signing-key", "/k", "--state-dir", "/var/lib/x"});
    ASSERT_TRUE(given.options) << given.text;
    EXPECT_EQ(given.options->signing_key, "/k");
    EXPECT_EQ(given.options->state_dir, "/var/lib/x");
    // systemd's StateDirectory= ($STATE_DIRECTORY, the first of a list)
    const auto systemd = parse({"--signing-key", "/k"}, "", "/var/lib/gport-mavlink:/var/lib/o");
    ASSERT_TRUE(systemd.options) << systemd.text;
    EXPECT_EQ(systemd.options->state_dir, "/var/lib/gport-mavlink");
    const auto overridden = parse({"--state-dir", "/tmp/s"}, "", "/var/lib/gport-mavlink");
    EXPECT_EQ(overridden.options->state_dir, "/tmp/s");
}

TEST(Options, TrustAndSigningFromTheConfigSection) {
    const auto path = write_config(
        "{\"mavlink\": {\"sysid\": \"auto\", \"gcs_sysid\": [255, 250], "
        "\"signing_key\": \"/etc/gportd/mavlink.key\", \"state_dir\": \"/var/lib/g\"}}");
    auto out = parse({"--config", path});
    ASSERT_TRUE(out.options) << out.text;
    EXPECT_FALSE(out.options->sysid);
    EXPECT_EQ(out.options->gcs_sysids, (std::vector<std::uint8_t>{255, 250}));
    EXPECT_EQ(out.options->signing_key, "/etc/gportd/mavlink.key");
    EXPECT_EQ(out.options->state_dir, "/var/lib/g");
    out = parse({"--config", path, "--sysid", "3", "--gcs-sysid", "none"});
    ASSERT_TRUE(out.options) << out.text;
    EXPECT_EQ(out.options->sysid, 3);
    EXPECT_TRUE(out.options->gcs_sysids.empty());
    std::filesystem::remove(path);

    const auto single = write_config("{\"mavlink\": {\"gcs_sysid\": 250, \"sysid\": 2}}");
    out = parse({"--config", single});
    ASSERT_TRUE(out.options) << out.text;
    EXPECT_EQ(out.options->gcs_sysids, std::vector<std::uint8_t>{250});
    std::filesystem::remove(single);

    const auto keyless = write_config("{\"mavlink\": {\"signing_key\": \"/k\"}}");
    out = parse({"--config", keyless});
    EXPECT_EQ(out.exit_code, 78) << out.text;
    EXPECT_NE(out.text.find("needs a state directory"), std::string::npos);
    std::filesystem::remove(keyless);
}

TEST(Options, BadConfigExits78) {
    for (const std::string text :
         {"{\"mavlink\": {\"rate\": 5}}", "{\"mavlink\": {\"sysid\": 300}}",
          "{\"mavlink\": {\"sysid\": \"any\"}}", "{\"mavlink\": {\"gcs_sysid\": [255, 0]}}",
          "{\"mavlink\": {\"gcs_sysid\": \"255\"}}", "{\"mavlink\": {\"signing_key\": \"\"}}",
          "{\"mavlink\": {\"state_dir\": 5}}", "{\"mavlink\": 5}",
          "{\"mavlink\": {\"url\": \"udp:1\"}}", "{\"mavlink\": {\"lease_ms\": 1}}", "{nope",
          "{}"}) {
        const auto path = write_config(text);
        const auto out = parse({"--config", path});
        EXPECT_EQ(out.exit_code, 78) << text;
        EXPECT_NE(out.text.find(path), std::string::npos) << out.text;
        std::filesystem::remove(path);
    }
    EXPECT_EQ(parse({"--config", "/nonexistent/gport.json"}).exit_code, 78);
}

TEST(Options, CameraOnByDefaultOffWithNoCameraOrConfig) {
    EXPECT_TRUE(parse({}).options->camera);
    const auto off = parse({"--no-camera"});
    ASSERT_TRUE(off.options) << off.text;
    EXPECT_FALSE(off.options->camera);
    const auto path = write_config(R"({"mavlink": {"camera": false}})");
    const auto config = parse({"--config", path});
    ASSERT_TRUE(config.options) << config.text;
    EXPECT_FALSE(config.options->camera);
    std::filesystem::remove(path);
}

TEST(Options, TheGimbalCannotTakeTheCameraComponentId) {
    const auto clash = parse({"--compid", "100"});
    EXPECT_EQ(clash.exit_code, 64);
    EXPECT_NE(clash.text.find("camera component"), std::string::npos) << clash.text;
    EXPECT_NE(clash.text.find("--no-camera"), std::string::npos) << clash.text;
    const auto fine = parse({"--compid", "100", "--no-camera"});
    ASSERT_TRUE(fine.options) << fine.text;
    EXPECT_EQ(fine.options->compid, 100);
    const auto path = write_config(R"({"mavlink": {"camera": "yes"}})");
    EXPECT_EQ(parse({"--config", path}).exit_code, 78);
    std::filesystem::remove(path);
}

}  // namespace
}  // namespace gport::mavlink::bridge
