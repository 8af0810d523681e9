// Every class of problem in a config file, and that all of them are reported
// together with the key path and what is allowed.
#include <gtest/gtest.h>

#include "test_support.hpp"

namespace gport::config::test {
namespace {

using ::testing::Contains;
using ::testing::ElementsAre;
using ::testing::SizeIs;

// One numeric key and its allowed range.
struct Range {
    const char* section;
    const char* key;
    std::int64_t min;
    std::int64_t max;
    const char* partner = "";  // keeps the other side of a pair check satisfied
};

const Range kRanges[] = {
    {"socket", "line_limit", 1024, 16 * 1024 * 1024},
    {"socket", "max_clients", 1, 4096, R"("reserved_command_slots": 0, )"},
    {"socket", "queue_limit", 8, 65536},
    {"socket", "max_clients_per_uid", 1, 4096},
    {"socket", "reserved_command_slots", 0, 4095, R"("max_clients": 4096, )"},
    {"socket", "idle_timeout_ms", 100, 86400000},
    {"socket", "max_requests_per_s", 1, 100000},
    {"keepalive", "rate_hz", 1, 50},
    {"keepalive", "default_duration_ms", 100, 600000, R"("max_duration_ms": 600000, )"},
    {"keepalive", "max_duration_ms", 100, 600000, R"("default_duration_ms": 100, )"},
    {"link", "stale_ms", 50, 60000},
    {"link", "reconnect_initial_ms", 10, 60000, R"("reconnect_max_ms": 600000, )"},
    {"link", "reconnect_max_ms", 10, 600000, R"("reconnect_initial_ms": 10, )"},
    {"requests", "timeout_ms", 10, 10000},
    {"requests", "retries", 0, 10},
    {"realtime", "priority", 0, 99},
};

std::string one_key(const Range& r, const std::string& value) {
    return std::string("{\"") + r.section + "\": {" + r.partner + "\"" + r.key + "\": " + value +
           "}}";
}

std::string path_of(const Range& r) {
    return std::string(r.section) + "." + r.key;
}

TEST(ConfigRanges, BothEndsAreAccepted) {
    for (const auto& r : kRanges) {
        for (auto n : {r.min, r.max}) {
            auto result = load(one_key(r, std::to_string(n)));
            EXPECT_TRUE(result.ok()) << path_of(r) << "=" << n << ": " << result.error().text();
        }
    }
}

TEST(ConfigRanges, JustOutsideEitherEndIsRefusedWithTheRange) {
    for (const auto& r : kRanges) {
        for (auto n : {r.min - 1, r.max + 1}) {
            EXPECT_THAT(
                errors_of(one_key(r, std::to_string(n))),
                ElementsAre(ErrorWith("test.json: ", path_of(r) + ": ", std::to_string(r.min),
                                      std::to_string(r.max), "got " + std::to_string(n))));
        }
    }
}

TEST(ConfigRanges, HugeAndNegativeNumbersDoNotWrap) {
    for (const char* n : {"18446744073709551615", "-9223372036854775808", "-1"}) {
        EXPECT_THAT(errors_of(std::string(R"({"socket": {"max_clients": )") + n + "}}"),
                    ElementsAre(ErrorWith("socket.max_clients", "from 1 to 4096")));
    }
}

TEST(ConfigTypes, WrongTypesNameTheKeyAndTheExpectedType) {
    EXPECT_THAT(
        errors_of(R"({"serial": {"baud": "fast"}})"),
        ElementsAre(ErrorWith("serial.baud", "standard serial rates", "115200", "got \"fast\"")));
    EXPECT_THAT(errors_of(R"({"serial": {"device": 5}})"),
                ElementsAre(ErrorWith("serial.device", "must be a string", "got 5")));
    EXPECT_THAT(errors_of(R"({"socket": {"line_limit": 2048.5}})"),
                ElementsAre(ErrorWith("socket.line_limit", "must be an integer", "got 2048.5")));
    EXPECT_THAT(errors_of(R"({"requests": {"retries": true}})"),
                ElementsAre(ErrorWith("requests.retries", "must be an integer", "got true")));
    EXPECT_THAT(errors_of(R"({"keepalive": {"rate_hz": null}})"),
                ElementsAre(ErrorWith("keepalive.rate_hz", "must be a number", "got null")));
    EXPECT_THAT(errors_of(R"({"log": {"level": ["info"]}})"),
                ElementsAre(ErrorWith("log.level", "must be a string", "got an array")));
    EXPECT_THAT(errors_of(R"({"access": {"control_uids": 1000}})"),
                ElementsAre(ErrorWith("access.control_uids", "must be an array", "got 1000")));
    EXPECT_THAT(errors_of(R"({"access": {"control_gids": [{"id": 1}]}})"),
                ElementsAre(ErrorWith("access.control_gids[0]", "group name or a numeric id",
                                      "got an object")));
}

TEST(ConfigTypes, SectionAndFileMustBeObjects) {
    EXPECT_THAT(errors_of(R"({"serial": "/dev/ttyUSB0"})"),
                ElementsAre(ErrorWith("serial: must be an object with the keys device, baud",
                                      "got \"/dev/ttyUSB0\"")));
    EXPECT_THAT(errors_of("[1, 2]"),
                ElementsAre(ErrorWith("test.json: the file must hold one JSON object",
                                      "serial, socket, keepalive", "got an array")));
}

TEST(ConfigKeys, UnknownTopLevelKeyListsTheSections) {
    EXPECT_THAT(
        errors_of(R"({"seriall": {}})"),
        ElementsAre(ErrorWith("test.json: unknown key \"seriall\"; allowed keys: serial, socket, "
                              "keepalive, link, requests, access, log")));
}

TEST(ConfigKeys, UnknownNestedKeyListsTheSectionsKeys) {
    EXPECT_THAT(errors_of(R"({"socket": {"path": "/run/x.sock", "permissions": "0660"}})"),
                ElementsAre(ErrorWith("unknown key \"socket.permissions\"",
                                      "allowed keys in socket: path, mode, group, line_limit, "
                                      "max_clients, queue_limit, max_clients_per_uid, "
                                      "reserved_command_slots, idle_timeout_ms, "
                                      "max_requests_per_s")));
}

TEST(ConfigSlots, ReservedSlotsMustLeaveRoomForEveryoneElse) {
    EXPECT_THAT(errors_of(R"({"socket": {"max_clients": 8}})"),
                ElementsAre(ErrorWith("socket.reserved_command_slots (8) must be less than "
                                      "socket.max_clients (8)")));
    EXPECT_THAT(errors_of(R"({"socket": {"reserved_command_slots": 128}})"),
                ElementsAre(ErrorWith("(128) must be less than socket.max_clients (128, the "
                                      "default)")));
    EXPECT_TRUE(load(R"({"socket": {"max_clients": 8, "reserved_command_slots": 7}})").ok());
}

TEST(ConfigKeys, DuplicateKeysAreRefused) {
    EXPECT_THAT(errors_of(R"({"serial": {"baud": 9600, "baud": 19200}})"),
                ElementsAre(ErrorWith("\"serial.baud\" appears more than once")));
    EXPECT_THAT(errors_of(R"({"log": {}, "log": {}})"),
                ElementsAre(ErrorWith("\"log\" appears more than once")));
}

TEST(ConfigCrossField, DefaultDurationMustNotExceedMaximum) {
    EXPECT_THAT(
        errors_of(R"({"keepalive": {"default_duration_ms": 5000, "max_duration_ms": 2000}})"),
        ElementsAre(ErrorWith("keepalive.default_duration_ms (5000) must not exceed "
                              "keepalive.max_duration_ms (2000)")));
}

TEST(ConfigCrossField, TheMessageSaysWhenTheOtherSideIsTheDefault) {
    EXPECT_THAT(errors_of(R"({"keepalive": {"default_duration_ms": 90000}})"),
                ElementsAre(ErrorWith("(90000) must not exceed keepalive.max_duration_ms "
                                      "(60000, the default)")));
}

TEST(ConfigCrossField, ReconnectInitialMustNotExceedMaximum) {
    EXPECT_THAT(errors_of(R"({"link": {"reconnect_initial_ms": 1000, "reconnect_max_ms": 500}})"),
                ElementsAre(ErrorWith("link.reconnect_initial_ms (1000) must not exceed "
                                      "link.reconnect_max_ms (500)")));
}

TEST(ConfigCrossField, SkippedWhenOneSideIsItselfInvalid) {
    // Only the range error: comparing with the kept default would mislead.
    EXPECT_THAT(
        errors_of(R"({"keepalive": {"default_duration_ms": 90000, "max_duration_ms": 700000}})"),
        ElementsAre(ErrorWith("keepalive.max_duration_ms", "from 100 to 600000")));
}

TEST(ConfigCrossField, StillCheckedWhenAnotherKeyOfTheSectionIsInvalid) {
    EXPECT_THAT(errors_of(R"({"keepalive": {"rate_hz": 0, "default_duration_ms": 5000,
                                             "max_duration_ms": 2000}})"),
                ElementsAre(ErrorWith("keepalive.rate_hz"),
                            ErrorWith("keepalive.default_duration_ms (5000) must not exceed")));
}

TEST(ConfigValues, BadModeStrings) {
    for (const char* mode :
         {"\"0999\"", "\"1777\"", "\"rw-rw----\"", "\"\"", "\"07777\"", "\"-660\"", "432"}) {
        EXPECT_THAT(errors_of(std::string(R"({"socket": {"mode": )") + mode + "}}"),
                    ElementsAre(ErrorWith("socket.mode", "octal string from \"0000\" to \"0777\"",
                                          std::string("got ") + mode)))
            << mode;
    }
}

TEST(ConfigValues, NonStandardBaudRate) {
    EXPECT_THAT(errors_of(R"({"serial": {"baud": 115201}})"),
                ElementsAre(ErrorWith("serial.baud", "50, 75, 110", "4000000", "got 115201")));
    EXPECT_THAT(errors_of(R"({"serial": {"baud": -9600}})"),
                ElementsAre(ErrorWith("serial.baud", "got -9600")));
}

TEST(ConfigValues, UnknownLogLevel) {
    EXPECT_THAT(errors_of(R"({"log": {"level": "verbose"}})"),
                ElementsAre(ErrorWith("log.level", "trace, debug, info, warn, error, critical, off",
                                      "got \"verbose\"")));
}

TEST(ConfigValues, PathsMustBeAbsoluteAndFitASocketAddress) {
    EXPECT_THAT(errors_of(R"({"serial": {"device": "ttyUSB0"}})"),
                ElementsAre(ErrorWith("serial.device", "absolute path", "got \"ttyUSB0\"")));
    EXPECT_THAT(errors_of(R"({"serial": {"device": ""}})"),
                ElementsAre(ErrorWith("serial.device", "got an empty string")));
    const std::string long_path = "/run/" + std::string(103, 'x');  // 108 bytes
    EXPECT_THAT(errors_of(R"({"socket": {"path": ")" + long_path + "\"}}"),
                ElementsAre(ErrorWith("socket.path", "at most 107 bytes", "got 108 bytes")));
    EXPECT_THAT(errors_of(R"({"socket": {"path": "/run/a\u0000b"}})"),
                ElementsAre(ErrorWith("socket.path", "NUL")));
}

TEST(ConfigValues, UnknownUserAndGroupNames) {
    EXPECT_THAT(errors_of(R"({"access": {"control_uids": ["root", "gport-no-such-user"]}})"),
                ElementsAre(ErrorWith("access.control_uids[1]: unknown user "
                                      "\"gport-no-such-user\"")));
    EXPECT_THAT(errors_of(R"({"access": {"control_gids": [0, "gport-no-such-group"]}})"),
                ElementsAre(ErrorWith("access.control_gids[1]: unknown group "
                                      "\"gport-no-such-group\"")));
    EXPECT_THAT(errors_of(R"({"socket": {"group": "gport-no-such-group"}})"),
                ElementsAre(ErrorWith("socket.group: unknown group \"gport-no-such-group\"")));
}

TEST(ConfigValues, IdsOutOfRange) {
    EXPECT_THAT(errors_of(R"({"access": {"control_uids": [-1, 4294967295]}})"),
                ElementsAre(ErrorWith("access.control_uids[0]", "from 0 to 4294967294", "got -1"),
                            ErrorWith("access.control_uids[1]", "got 4294967295")));
}

TEST(ConfigSyntax, ErrorGivesFileLineColumnAndByte) {
    const auto errors = errors_of("{\n  \"serial\": {\n    \"baud\": 9600,\n  }\n}");
    EXPECT_THAT(errors, ElementsAre(ErrorWith("test.json: line 4, column 3 (byte 37): invalid "
                                              "JSON: ",
                                              "unexpected '}'")));
}

TEST(ConfigSyntax, EmptyTextAndTrailingGarbage) {
    EXPECT_THAT(errors_of(""),
                ElementsAre(ErrorWith("line 1, column 1", "unexpected end of input")));
    EXPECT_THAT(errors_of("{} {}"), ElementsAre(ErrorWith("line 1", "invalid JSON")));
}

TEST(ConfigSyntax, NumberTooLargeForADouble) {
    EXPECT_THAT(errors_of(R"({"keepalive": {"rate_hz": 1e400}})"),
                ElementsAre("test.json: invalid JSON: number overflow parsing '1e400'"));
}

TEST(ConfigSyntax, InvalidUtf8IsASyntaxError) {
    EXPECT_THAT(errors_of("{\"log\": {\"level\": \"\xff\"}}"),
                ElementsAre(ErrorWith("invalid JSON", "UTF-8")));
}

TEST(ConfigErrors, AllProblemsAreReportedInOnePass) {
    const auto errors = errors_of(R"({
        "serial": {"baud": 12345, "speed": 1},
        "socket": {"mode": "999", "max_clients": 0},
        "keepalive": {"rate_hz": 100},
        "access": {"control_uids": ["gport-no-such-user"]},
        "log": {"level": "loud"},
        "extra": true
    })");
    EXPECT_THAT(errors, SizeIs(8));
    EXPECT_THAT(errors, Contains(ErrorWith("serial.baud")));
    EXPECT_THAT(errors, Contains(ErrorWith("\"serial.speed\"")));
    EXPECT_THAT(errors, Contains(ErrorWith("socket.mode")));
    EXPECT_THAT(errors, Contains(ErrorWith("socket.max_clients")));
    EXPECT_THAT(errors, Contains(ErrorWith("keepalive.rate_hz")));
    EXPECT_THAT(errors, Contains(ErrorWith("access.control_uids[0]")));
    EXPECT_THAT(errors, Contains(ErrorWith("log.level")));
    EXPECT_THAT(errors, Contains(ErrorWith("\"extra\"")));
}

TEST(ConfigErrors, MessagesFollowTheOrderOfTheFile) {
    const auto errors = errors_of(R"({"log": {"level": 1}, "serial": {"baud": 1}})");
    EXPECT_THAT(errors, ElementsAre(ErrorWith("log.level"), ErrorWith("serial.baud")));
}

TEST(ConfigErrors, ErrorTextHasOneLinePerProblem) {
    auto result = load(R"({"a": 1, "b": 2})");
    ASSERT_FALSE(result.ok());
    EXPECT_EQ(result.error().text(),
              result.error().messages[0] + "\n" + result.error().messages[1] + "\n");
}

}  // namespace
}  // namespace gport::config::test
