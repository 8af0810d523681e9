// Defaults, the shipped example and fully valid files.
#include <gtest/gtest.h>

#include "test_support.hpp"

namespace gport::config::test {
namespace {

using ::testing::ElementsAre;
using ::testing::IsEmpty;
using namespace std::chrono_literals;

void expect_defaults(const Config& c) {
    EXPECT_EQ(c.serial.device, "/dev/gimbal");
    EXPECT_EQ(c.serial.baud, 115200u);
    EXPECT_EQ(c.socket.path, "/run/gportd.sock");
    EXPECT_EQ(c.socket.mode, 0660u);
    EXPECT_EQ(c.socket.group, "");
    EXPECT_EQ(c.socket.line_limit, 64u * 1024u);
    EXPECT_EQ(c.socket.max_clients, 128u);
    EXPECT_EQ(c.socket.queue_limit, 256u);
    EXPECT_EQ(c.socket.max_clients_per_uid, 64u);
    EXPECT_EQ(c.socket.reserved_command_slots, 8u);
    EXPECT_EQ(c.socket.idle_timeout, 300000ms);
    EXPECT_EQ(c.socket.max_requests_per_s, 200u);
    EXPECT_DOUBLE_EQ(c.keepalive.rate_hz, 10.0);
    EXPECT_EQ(c.keepalive.default_duration, 1000ms);
    EXPECT_EQ(c.keepalive.max_duration, 60000ms);
    EXPECT_EQ(c.link.stale_after, 500ms);
    EXPECT_EQ(c.link.reconnect_initial, 250ms);
    EXPECT_EQ(c.link.reconnect_max, 5000ms);
    EXPECT_EQ(c.requests.timeout, 300ms);
    EXPECT_EQ(c.requests.retries, 2u);
    EXPECT_THAT(c.access.control_uids, IsEmpty());
    EXPECT_THAT(c.access.control_gids, IsEmpty());
    EXPECT_EQ(c.log.level, "info");
    EXPECT_FALSE(c.simulate);
}

TEST(ConfigDefaults, BuiltInValues) {
    expect_defaults(Config{});
}

TEST(ConfigDefaults, EmptyObjectKeepsEveryDefault) {
    auto result = load("{}");
    ASSERT_TRUE(result.ok()) << result.error().text();
    expect_defaults(*result);
}

TEST(ConfigDefaults, EmptySectionsKeepEveryDefault) {
    auto result = load(R"({"serial": {}, "socket": {}, "keepalive": {}, "link": {},
                          "requests": {}, "access": {}, "log": {}})");
    ASSERT_TRUE(result.ok()) << result.error().text();
    expect_defaults(*result);
}

TEST(ConfigExample, ShippedFileLoadsAndMatchesTheDefaults) {
    auto result = load_config_file(GPORT_EXAMPLE_CONFIG);
    ASSERT_TRUE(result.ok()) << result.error().text();
    expect_defaults(*result);
}

TEST(ConfigFile, FullValidFileSetsEveryKey) {
    auto result = load(R"({
        "serial": {"device": "/dev/ttyUSB3", "baud": 921600},
        "socket": {"path": "/tmp/g.sock", "mode": "0600", "group": "root",
                   "line_limit": 1024, "max_clients": 4096, "queue_limit": 8,
                   "max_clients_per_uid": 3, "reserved_command_slots": 2,
                   "idle_timeout_ms": 1500, "max_requests_per_s": 50},
        "keepalive": {"rate_hz": 2.5, "default_duration_ms": 100, "max_duration_ms": 600000},
        "link": {"stale_ms": 50, "reconnect_initial_ms": 10, "reconnect_max_ms": 600000},
        "requests": {"timeout_ms": 10000, "retries": 0},
        "access": {"control_uids": [0, 1000, "root"], "control_gids": ["root", 44]},
        "log": {"level": "trace"}
    })");
    ASSERT_TRUE(result.ok()) << result.error().text();
    const Config& c = *result;
    EXPECT_EQ(c.serial.device, "/dev/ttyUSB3");
    EXPECT_EQ(c.serial.baud, 921600u);
    EXPECT_EQ(c.socket.path, "/tmp/g.sock");
    EXPECT_EQ(c.socket.mode, 0600u);
    EXPECT_EQ(c.socket.group, "root");
    EXPECT_EQ(c.socket.line_limit, 1024u);
    EXPECT_EQ(c.socket.max_clients, 4096u);
    EXPECT_EQ(c.socket.queue_limit, 8u);
    EXPECT_EQ(c.socket.max_clients_per_uid, 3u);
    EXPECT_EQ(c.socket.reserved_command_slots, 2u);
    EXPECT_EQ(c.socket.idle_timeout, 1500ms);
    EXPECT_EQ(c.socket.max_requests_per_s, 50u);
    EXPECT_DOUBLE_EQ(c.keepalive.rate_hz, 2.5);
    EXPECT_EQ(c.keepalive.default_duration, 100ms);
    EXPECT_EQ(c.keepalive.max_duration, 600000ms);
    EXPECT_EQ(c.link.stale_after, 50ms);
    EXPECT_EQ(c.link.reconnect_initial, 10ms);
    EXPECT_EQ(c.link.reconnect_max, 600000ms);
    EXPECT_EQ(c.requests.timeout, 10000ms);
    EXPECT_EQ(c.requests.retries, 0u);
    EXPECT_THAT(c.access.control_uids, ElementsAre(0u, 1000u, 0u));  // "root" is uid 0
    EXPECT_THAT(c.access.control_gids, ElementsAre(0u, 44u));
    EXPECT_EQ(c.log.level, "trace");
    EXPECT_FALSE(c.simulate);  // command line only
}

TEST(ConfigFile, PartialSectionKeepsTheOtherDefaults) {
    auto result = load(R"({"keepalive": {"rate_hz": 20}})");
    ASSERT_TRUE(result.ok()) << result.error().text();
    EXPECT_DOUBLE_EQ(result->keepalive.rate_hz, 20.0);
    EXPECT_EQ(result->keepalive.default_duration, 1000ms);
    EXPECT_EQ(result->serial.device, "/dev/gimbal");
}

TEST(ConfigFile, LineAndBlockCommentsAreAllowed) {
    auto result = load(R"(// leading comment
        {
            /* block comment
               over lines */
            "serial": { // trailing comment
                "baud": /* inline */ 9600
            }
        }
        // final comment)");
    ASSERT_TRUE(result.ok()) << result.error().text();
    EXPECT_EQ(result->serial.baud, 9600u);
}

TEST(ConfigFile, ModeAcceptsShortAndZeroForms) {
    for (const auto& [text, mode] : {std::pair{"0", 0u}, std::pair{"660", 0660u},
                                     std::pair{"0777", 0777u}, std::pair{"0000", 0u}}) {
        auto result = load(std::string(R"({"socket": {"mode": ")") + text + "\"}}");
        ASSERT_TRUE(result.ok()) << text << ": " << result.error().text();
        EXPECT_EQ(result->socket.mode, mode) << text;
    }
}

TEST(ConfigFile, EveryLogLevelIsAccepted) {
    for (const char* level : {"trace", "debug", "info", "warn", "error", "critical", "off"}) {
        auto result = load(std::string(R"({"log": {"level": ")") + level + "\"}}");
        ASSERT_TRUE(result.ok()) << level << ": " << result.error().text();
        EXPECT_EQ(result->log.level, level);
    }
}

TEST(ConfigFile, LowAndHighStandardBaudRatesAreAccepted) {
    for (unsigned baud : {50u, 9600u, 4000000u}) {
        auto result = load(R"({"serial": {"baud": )" + std::to_string(baud) + "}}");
        ASSERT_TRUE(result.ok()) << baud << ": " << result.error().text();
        EXPECT_EQ(result->serial.baud, baud);
    }
}

TEST(ConfigFile, LargestUidIsAccepted) {
    auto result = load(R"({"access": {"control_uids": [4294967294]}})");
    ASSERT_TRUE(result.ok()) << result.error().text();
    EXPECT_THAT(result->access.control_uids, ElementsAre(4294967294u));
}

}  // namespace
}  // namespace gport::config::test
