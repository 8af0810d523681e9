// CaptureLog, the capture log's memory: restore, the indexes, bounds, pages
// and the sink's durable mark.
#include "gport/capture/capture_log.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "fake_capture_sink.hpp"

namespace gport::capture {
namespace {

using gport::testing::FakeSink;
using nlohmann::json;
using ::testing::HasSubstr;

// The log's own calls, read back as JSON.
json page(const CaptureLog& log, std::uint64_t since, std::size_t limit) {
    return json::parse(log.list(since, limit));
}

json add(CaptureLog& log, const json& capture = json::object(), std::string_view kind = "photo") {
    auto prepared = log.prepare(capture);
    EXPECT_TRUE(std::holds_alternative<CaptureLog::Prepared>(prepared));
    return json::parse(log.add(std::get<CaptureLog::Prepared>(std::move(prepared)), kind).text);
}

TEST(CaptureLog, RestoreContinuesAfterTheHighestIndexAndSkipsBrokenLines) {
    CaptureLog log(3);
    log.restore({R"({"index":7,"kind":"photo"})", R"({"index":8,"kind":"photo"})", "{\"ind",
                 R"({"index":"9"})", "[]", R"({"index":9,"kind":"record_start"})",
                 R"({"index":10,"kind":"record_stop"})"},
                1);
    EXPECT_EQ(log.next_index(), 11u);
    const auto all = page(log, 0, 100);
    ASSERT_EQ(all["captures"].size(), 3u) << "only the newest `kept`";
    EXPECT_EQ(all["captures"][0]["index"], 8);
    EXPECT_EQ(add(log)["index"], 11);
    EXPECT_EQ(page(log, 0, 100)["captures"][0]["index"], 9);
}

TEST(CaptureLog, RestoredNextIndexWinsWhenHigher) {
    CaptureLog log;
    log.restore({}, 42);
    EXPECT_EQ(add(log)["index"], 42);
}

// A crafted log: lines out of order, a duplicate, a line nested 100,000
// deep, indexes that would wrap (2^64 - 2, UINT64_MAX) or are not JSON-safe.
TEST(CaptureLog, ACraftedLogCannotWrapTheIndexOrBreakOrder) {
    CaptureLog log;
    const std::string deep = std::string(100000, '[') + std::string(100000, ']');
    log.restore(
        {R"({"index":5,"kind":"photo"})", R"({"index":3,"kind":"photo"})",
         R"({"index":4,"kind":"photo"})", R"({"index":3,"kind":"record_start"})",
         "{\"index\":6,\"meta\":" + deep + "}", R"({"index":18446744073709551614})",
         R"({"index":18446744073709551615})", R"({"index":9007199254740992})", R"({"index":0})"},
        1);
    EXPECT_EQ(log.next_index(), 6u) << "only 3, 4 and 5 are captures";
    const auto all = page(log, 0, 100);
    ASSERT_EQ(all["captures"].size(), 3u);
    EXPECT_EQ(all["captures"][0]["index"], 3);
    EXPECT_EQ(all["captures"][2]["index"], 5);
    EXPECT_EQ(page(log, 4, 100)["captures"][0]["index"], 4) << "since works on any order";
    EXPECT_EQ(all["next"], 6);
}

TEST(CaptureLog, TheLastJsonSafeIndexIsGivenOnceThenNoMore) {
    CaptureLog log;
    log.restore({}, CaptureLog::kMaxIndex);
    EXPECT_EQ(add(log)["index"], CaptureLog::kMaxIndex);
    const auto refused = log.prepare(json::object());
    ASSERT_TRUE(std::holds_alternative<std::string>(refused));
    EXPECT_THAT(std::get<std::string>(refused), HasSubstr("every index"));
}

// A process name cut mid-character by the kernel: the capture is built with
// U+FFFD before anything is sent, never an exception after.
TEST(CaptureLog, InvalidUtf8IsReplacedWhenPrepared) {
    CaptureLog log;
    FakeSink sink;
    log.set_sink(&sink);
    const auto capture = add(log, json{{"client", {{"name", std::string("photos_f\xc3")}}}});
    EXPECT_EQ(capture["client"]["name"], "photos_f\xef\xbf\xbd");
    ASSERT_EQ(sink.lines.size(), 1u);
    json line;
    EXPECT_NO_THROW(line = json::parse(sink.lines[0]));
    EXPECT_EQ(line["client"]["name"], "photos_f\xef\xbf\xbd");
}

// Pages are bounded by bytes as well as by count, so a reply always fits a
// client's output limit, and "more"/"next" page through everything.
TEST(CaptureLog, PagesAreBoundedByBytesAndPageThroughEverything) {
    CaptureLog log;
    const json meta = {{"s", std::string(1000, 'x')}};
    for (int i = 0; i < 1000; ++i) {
        add(log, json{{"meta", meta}});
    }
    std::uint64_t since = 0;
    std::size_t seen = 0;
    int pages = 0;
    for (;; ++pages) {
        const auto text = log.list(since, CaptureLog::kMaxLimit);
        EXPECT_LE(text.size(), CaptureLog::kMaxPageBytes + 64);
        const auto reply = json::parse(text);
        seen += reply["captures"].size();
        since = reply["next"];
        if (!reply["more"].get<bool>()) {
            break;
        }
    }
    EXPECT_EQ(seen, 1000u);
    EXPECT_GT(pages, 10);
    EXPECT_EQ(since, 1001u);
}

class ReservingSink final : public CaptureSink {
  public:
    void write(std::string line) override { lines.push_back(std::move(line)); }
    void reserve(std::uint64_t upto) override { asked.push_back(upto); }
    std::optional<std::uint64_t> reserved() const override { return durable; }
    Stats stats() const override { return Stats{0, 0, std::string("No space left on device")}; }
    std::string path() const override { return "/var/lib/gportd/captures.jsonl"; }
    std::vector<std::string> lines;
    std::vector<std::uint64_t> asked;
    std::optional<std::uint64_t> durable;
};

// An index is given only below the durable high-water mark: a stalled or
// full disk that cannot move the mark refuses captures (nothing is sent)
// rather than give an index a restart could give again.
TEST(CaptureLog, NoIndexIsGivenBeyondTheDurableMark) {
    CaptureLog log;
    ReservingSink sink;
    sink.durable = 10;
    log.set_sink(&sink);
    log.restore({}, 1);
    for (int i = 1; i < 10; ++i) {
        EXPECT_EQ(add(log)["index"], i);
    }
    ASSERT_FALSE(sink.asked.empty()) << "asked ahead, well before the mark";
    EXPECT_EQ(sink.asked.front(), 1u + CaptureLog::kReserveAhead);
    const auto asked = sink.asked.size();
    const auto refused = log.prepare(json::object());
    ASSERT_TRUE(std::holds_alternative<std::string>(refused));
    EXPECT_THAT(std::get<std::string>(refused), HasSubstr("No space left on device"));
    EXPECT_THAT(std::get<std::string>(refused), HasSubstr("index 10"));
    EXPECT_GT(sink.asked.size(), asked) << "a refused capture asks again: the disk may be back";
    sink.durable = 1000;
    EXPECT_EQ(add(log)["index"], 10) << "the next index once the mark moved";
    EXPECT_EQ(log.status()["reserved"], 1000);
}

}  // namespace
}  // namespace gport::capture
