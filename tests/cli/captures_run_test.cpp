// gportctl captures against a scripted gportd (tests/client/hostile_server.hpp):
// pages bounded in bytes (fewer captures than asked for, `more` true), an
// older gportd without `more`, --limit as the total printed, and a log whose
// texts attack the reader's terminal and spreadsheet (issue 30).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <mutex>
#include <sstream>

#include "gport/cli/run.hpp"
#include "hostile_server.hpp"
#include "rfc4180.hpp"

namespace gport::cli::captures_run_test {
namespace {

using nlohmann::json;
using ::testing::HasSubstr;
using testing::HostilePeer;
using testing::HostileServer;
using testing::quoted_csv_fields;

struct Ran {
    int status;
    std::string out;
    std::string err;
};

Ran run(const HostileServer& server, std::vector<std::string> args) {
    args.insert(args.begin(), {"--socket", server.path()});
    std::ostringstream out;
    std::ostringstream err;
    const int status = main_with(args, nullptr, out, err, [] { return false; }, {});
    return {status, out.str(), err.str()};
}

json capture(std::uint64_t index, const std::string& name = "gport-mavlink") {
    return {{"index", index},
            {"kind", "photo"},
            {"utc_us", 1795563183085470},
            {"attitude", nullptr},
            {"client", {{"pid", 40}, {"uid", 0}, {"name", name}}}};
}

// A gportd holding captures 1..total that lists at most `per_page` at a time
// (its byte bound), with `more` unless `old`; records each `since` asked.
class PagingDaemon {
  public:
    PagingDaemon(std::uint64_t total, std::uint64_t per_page, bool old)
        : server_([this, total, per_page, old](HostilePeer& peer, const json& request) {
              const auto since = std::max<std::uint64_t>(request["params"].value("since", 0), 1);
              const auto limit = request["params"].value("limit", std::uint64_t{100});
              json list = json::array();
              for (auto i = since; i <= total && list.size() < std::min(limit, per_page); ++i) {
                  list.push_back(capture(i));
              }
              const auto next =
                  list.empty() ? total + 1 : list.back()["index"].get<std::uint64_t>() + 1;
              json result = {{"captures", list}, {"next", next}};
              if (!old) {
                  result["more"] = next <= total;
              }
              record(since);
              peer.reply(request, result);
          }) {}

    const HostileServer& server() const { return server_; }
    std::vector<std::uint64_t> asked() {
        const std::lock_guard lock(mutex_);
        return asked_;
    }

  private:
    void record(std::uint64_t since) {
        const std::lock_guard lock(mutex_);
        asked_.push_back(since);
    }
    std::mutex mutex_;
    std::vector<std::uint64_t> asked_;
    HostileServer server_;
};

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        out.push_back(line);
    }
    return out;
}

TEST(CapturesPaging, AShortPageWithMoreIsNotTheEnd) {
    PagingDaemon daemon(7, 3, false);
    const auto ran = run(daemon.server(), {"captures", "--csv"});
    ASSERT_EQ(ran.status, kExitOk) << ran.err;
    const auto rows = lines(ran.out);
    ASSERT_EQ(rows.size(), 8u) << ran.out;
    for (std::size_t i = 1; i < rows.size(); ++i) {
        EXPECT_EQ((*quoted_csv_fields(rows[i]))[0], std::to_string(i));
    }
    EXPECT_EQ(daemon.asked(), (std::vector<std::uint64_t>{1, 4, 7}));
}

TEST(CapturesPaging, AnOlderGportdIsAskedUntilAPageIsEmpty) {
    PagingDaemon daemon(5, 2, true);
    const auto ran = run(daemon.server(), {"--json", "captures"});
    ASSERT_EQ(ran.status, kExitOk) << ran.err;
    const auto rows = lines(ran.out);
    ASSERT_EQ(rows.size(), 5u) << ran.out;
    EXPECT_EQ(json::parse(rows.back())["index"], 5);
    EXPECT_EQ(daemon.asked(), (std::vector<std::uint64_t>{1, 3, 5, 6}));
}

TEST(CapturesPaging, LimitIsTheTotalPrintedAcrossPagesFromSince) {
    PagingDaemon daemon(20, 3, false);
    const auto ran = run(daemon.server(), {"captures", "--since", "4", "--limit", "7"});
    ASSERT_EQ(ran.status, kExitOk) << ran.err;
    const auto rows = lines(ran.out);
    ASSERT_EQ(rows.size(), 8u) << "a header and seven captures:\n" << ran.out;
    EXPECT_THAT(rows[1], HasSubstr("      4  "));
    EXPECT_THAT(rows[7], HasSubstr("     10  "));
    EXPECT_EQ(daemon.asked(), (std::vector<std::uint64_t>{4, 7, 10}));
}

// A gportd saying `more` forever without advancing does not keep gportctl.
TEST(CapturesPaging, ANextThatDoesNotAdvanceEndsTheListing) {
    HostileServer server([](HostilePeer& peer, const json& request) {
        peer.reply(request, {{"captures", {capture(1)}}, {"next", 1}, {"more", true}});
    });
    const auto ran = run(server, {"captures", "--since", "1"});
    EXPECT_EQ(ran.status, kExitOk);
    EXPECT_EQ(lines(ran.out).size(), 2u) << "a header and the one page";
}

// The attack: another client's name and meta, and a crafted log's kind.
json hostile_capture() {
    auto c = capture(1,
                     "\x1b[2J\x1b]0;owned\x07\xc2\x9b"
                     "31m\xef\xbf\xbd");
    c["kind"] = "=cmd|'/C calc'!A0";
    c["meta"] = {{"lat", "=1+1"}, {"lon", -30.5}, {"note", "\x1b[2J"}};
    return c;
}

bool has_raw_control(std::string_view bytes) {
    for (std::size_t i = 0; i < bytes.size(); ++i) {
        const auto c = static_cast<unsigned char>(bytes[i]);
        const auto next = i + 1 < bytes.size() ? static_cast<unsigned char>(bytes[i + 1]) : 0;
        if ((c < 0x20 && c != '\n') || c == 0x7F || (c == 0xC2 && next >= 0x80 && next <= 0x9F)) {
            return true;
        }
    }
    return false;
}

HostileServer hostile_log() {
    return HostileServer([](HostilePeer& peer, const json& request) {
        peer.reply(request, {{"captures", {hostile_capture()}}, {"next", 2}, {"more", false}});
    });
}

TEST(CapturesAttack, TheTableShowsEscapesNotControls) {
    const auto server = hostile_log();
    const auto ran = run(server, {"captures"});
    ASSERT_EQ(ran.status, kExitOk) << ran.err;
    EXPECT_FALSE(has_raw_control(ran.out)) << ran.out;
    EXPECT_THAT(ran.out, HasSubstr("\\x1b[2J\\x1b]0;owned\\x07\\u009b31m\xef\xbf\xbd (pid 40)"));
}

TEST(CapturesAttack, TheCsvIsQuotedAndHoldsNoFormula) {
    const auto server = hostile_log();
    const auto ran = run(server, {"captures", "--csv"});
    ASSERT_EQ(ran.status, kExitOk) << ran.err;
    EXPECT_FALSE(has_raw_control(ran.out));
    const auto rows = lines(ran.out);
    ASSERT_EQ(rows.size(), 2u);
    const auto fields = quoted_csv_fields(rows[1]);
    ASSERT_TRUE(fields) << rows[1];
    ASSERT_EQ(fields->size(), 20u);
    EXPECT_EQ((*fields)[2], "'=cmd|'/C calc'!A0");
    EXPECT_EQ((*fields)[9], "");
    EXPECT_EQ((*fields)[10], "-30.5");
}

TEST(CapturesAttack, JsonLinesEscapeEveryControlAndParseBack) {
    const auto server = hostile_log();
    const auto ran = run(server, {"--json", "captures"});
    ASSERT_EQ(ran.status, kExitOk) << ran.err;
    EXPECT_FALSE(has_raw_control(ran.out)) << ran.out;
    EXPECT_EQ(json::parse(lines(ran.out)[0]), hostile_capture());
}

// A gportd whose status holds controls and which refuses everything else.
HostileServer hostile_daemon() {
    return HostileServer([](HostilePeer& peer, const json& request) {
        if (request["method"] == "status") {
            peer.reply(request, {{"link", {{"state", "down"}, {"reason", "\x1b[2Jr"}}},
                                 {"device", "/dev/\x1b]0;x\x07"},
                                 {"device_error", "\xc2\x9b"},
                                 {"daemon_version", "1\x1b[31m"}});
            return;
        }
        peer.send_line({{"jsonrpc", "2.0"},
                        {"id", request["id"]},
                        {"error", {{"code", -32000}, {"message", "no\x1b[2J\r\nway"}}}});
    });
}

TEST(PrintedText, ARefusalsMessageAndAStatusAreEscaped) {
    const auto for_status = hostile_daemon();
    const auto status = run(for_status, {"status"});
    EXPECT_FALSE(has_raw_control(status.out)) << status.out;
    EXPECT_THAT(status.out, HasSubstr("device:    /dev/\\x1b]0;x\\x07 (closed: \\u009b)"));
    const auto for_photo = hostile_daemon();
    const auto refused = run(for_photo, {"photo"});
    EXPECT_EQ(refused.status, kExitError);
    EXPECT_FALSE(has_raw_control(refused.err)) << refused.err;
    EXPECT_THAT(refused.err, HasSubstr("error -32000: no\\x1b[2J\\x0d\\x0away"));
}

}  // namespace
}  // namespace gport::cli::captures_run_test
