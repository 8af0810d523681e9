// Issue 30: what a client or gportd supplied is printed without a byte a
// terminal acts on (printable, json_line), and the capture CSV is RFC 4180
// with no cell a spreadsheet runs as a formula.
#include "gport/cli/printable.hpp"

#include <gtest/gtest.h>

#include "gport/cli/captures.hpp"
#include "rfc4180.hpp"

namespace gport::cli::printable_test {
namespace {

using nlohmann::json;
using testing::quoted_csv_fields;

// No C0 control but the line's end, no DEL, no UTF-8-encoded C1 control.
bool terminal_safe(std::string_view bytes) {
    for (std::size_t i = 0; i < bytes.size(); ++i) {
        const auto c = static_cast<unsigned char>(bytes[i]);
        const auto next = i + 1 < bytes.size() ? static_cast<unsigned char>(bytes[i + 1]) : 0;
        if ((c < 0x20 && c != '\n') || c == 0x7F || (c == 0xC2 && next >= 0x80 && next <= 0x9F)) {
            return false;
        }
    }
    return true;
}

struct Attack {
    const char* name;
    std::string text;
    std::string shown;
};

const std::vector<Attack>& attacks() {
    static const std::vector<Attack> kAttacks = {
        {"clear screen", "\x1b[2Jgone", "\\x1b[2Jgone"},
        {"OSC 0 retitle", "\x1b]0;owned\x07", "\\x1b]0;owned\\x07"},
        {"C1 CSI",
         "a\xc2\x9b"
         "2Jb",
         "a\\u009b2Jb"},
        {"C1 range ends", "\xc2\x80\xc2\x9f\xc2\xa0", "\\u0080\\u009f\xc2\xa0"},
        {"DEL, NUL, tab, CR, LF", std::string("x\x7f\0\t\r\ny", 7), "x\\x7f\\x00\\x09\\x0d\\x0ay"},
        {"a lone continuation byte",
         "a\x9b"
         "b",
         "a\\x9bb"},
        {"a cut sequence", "f\xc3", "f\\xc3"},
        {"overlong ESC", "\xc0\x9b", "\\xc0\\x9b"},
        {"overlong slash", "\xe0\x80\xaf", "\\xe0\\x80\\xaf"},
        {"a surrogate", "\xed\xa0\x80", "\\xed\\xa0\\x80"},
        {"past U+10FFFF", "\xf4\x90\x80\x80", "\\xf4\\x90\\x80\\x80"},
        {"0xFF", "\xff", "\\xff"},
    };
    return kAttacks;
}

TEST(Printable, ControlsAndInvalidUtf8AreShownVisibly) {
    for (const auto& attack : attacks()) {
        EXPECT_EQ(printable(attack.text), attack.shown) << attack.name;
        EXPECT_TRUE(terminal_safe(printable(attack.text))) << attack.name;
    }
}

TEST(Printable, PrintableUtf8IsKeptAsItIs) {
    for (const std::string text :
         {"für", "gport-mavlink", "a\\x1b b", "€ 𝄞 ✓ 日本", "\xc2\xa0nbsp", "\xf4\x8f\xbf\xbf"}) {
        EXPECT_EQ(printable(text), text);
    }
}

TEST(JsonLine, DelAndC1AreEscapedTheRestIsNlohmannsDump) {
    const json value = {{"name", "\x1b[2J\x7f\xc2\x9b für"}, {"n", -30.5}};
    const auto line = json_line(value);
    EXPECT_EQ(line, R"({"n":-30.5,"name":"\u001b[2J\u007f\u009b für"})");
    EXPECT_EQ(json::parse(line), value) << "the same JSON value";
    const json plain = {{"kind", "photo"}, {"meta", {{"lat", 47.397742}}}};
    EXPECT_EQ(json_line(plain), plain.dump()) << "byte-exact otherwise";
    EXPECT_EQ(json_line(json("\xff")), "\"\xef\xbf\xbd\"") << "no throw";
}

json crafted_capture() {
    return {{"index", 7},
            {"kind", "=cmd|'/C calc'!A0"},
            {"utc_us", 1795563183085470},
            {"attitude",
             {{"imu", {{"roll", 0.5}, {"pitch", -30.5}, {"yaw", 1e-7}}},
              {"hall", {{"roll", "=1+1"}, {"pitch", -29.98}, {"yaw", 45.01}}}}},
            {"client", {{"pid", 12}, {"name", "\x1b]0;owned\x07\xc2\x9b"}}},
            {"meta", {{"lat", "=HYPERLINK(\"x\")"}, {"lon", 8.5}, {"alt_m", "@SUM(1)"}}}};
}

TEST(CapturesCsv, EveryFieldQuotedAFormulaInATextCellDefused) {
    const auto row = capture_csv_row(crafted_capture());
    ASSERT_EQ(row.back(), '\n');
    EXPECT_TRUE(terminal_safe(row));
    const auto fields = quoted_csv_fields(row.substr(0, row.size() - 1));
    ASSERT_TRUE(fields) << row;
    ASSERT_EQ(fields->size(), 20u) << row;
    EXPECT_EQ((*fields)[0], "7");
    EXPECT_EQ((*fields)[1], "2026-11-24T23:33:03.085470Z");
    EXPECT_EQ((*fields)[2], "'=cmd|'/C calc'!A0") << "text, not a formula";
    EXPECT_EQ((*fields)[4], "-30.5") << "a negative number stays a number";
    EXPECT_EQ((*fields)[5], "1e-07");
    EXPECT_EQ((*fields)[6], "") << "a string where a number belongs is left out";
    EXPECT_EQ((*fields)[9], "");
    EXPECT_EQ((*fields)[10], "8.5");
    EXPECT_EQ((*fields)[11], "");
}

TEST(CapturesCsv, QuotesAreDoubledControlsEscapedAndEachLeadDefused) {
    for (const auto& [kind, cell] :
         std::vector<std::pair<std::string, std::string>>{{"a\"b,c", "a\"b,c"},
                                                          {"+1", "'+1"},
                                                          {"-1+cmd", "'-1+cmd"},
                                                          {"@x", "'@x"},
                                                          {"\t=1", "\\x09=1"},
                                                          {"\r=1", "\\x0d=1"},
                                                          {"\x1b[2J", "\\x1b[2J"},
                                                          {"photo", "photo"}}) {
        const auto row = capture_csv_row({{"index", 1}, {"kind", kind}});
        const auto fields = quoted_csv_fields(row.substr(0, row.size() - 1));
        ASSERT_TRUE(fields) << row;
        EXPECT_EQ((*fields)[2], cell) << row;
    }
}

TEST(CapturesTable, TheClientNameAndKindArePrintable) {
    const auto row = capture_table_row(crafted_capture());
    EXPECT_TRUE(terminal_safe(row)) << row;
    EXPECT_NE(row.find("\\x1b]0;owned\\x07\\u009b (pid 12)"), std::string::npos) << row;
}

// POSITION sits under its header: a row's position starts where the
// header's word does.
std::string position_cell(const json& capture) {
    const auto at = captures_table_header().find("POSITION");
    const auto row = capture_table_row(capture);
    EXPECT_NE(at, std::string::npos);
    EXPECT_GT(row.size(), at) << row;
    const auto cell = row.substr(at);
    return cell.substr(0, cell.find("  "));
}

TEST(CapturesTable, APositionShowsLatLonAndAltitude) {
    json capture = {{"index", 3},
                    {"kind", "photo"},
                    {"utc_us", 1795563183085470},
                    {"meta", {{"lat", 47.397742}, {"lon", -8.545594}, {"alt_m", 488.2}}}};
    EXPECT_EQ(position_cell(capture), "47.397742,-8.545594 488.2m");
    capture["meta"].erase("alt_m");
    EXPECT_EQ(position_cell(capture), "47.397742,-8.545594");
    capture["meta"] = {{"wp", 3}};
    EXPECT_EQ(position_cell(capture), "-");
    capture.erase("meta");
    EXPECT_EQ(position_cell(capture), "-");
    capture["meta"] = "47,8";
    EXPECT_EQ(position_cell(capture), "-");
}

TEST(CapturesTable, APositionWithoutANumericLonShowsWhatIsThere) {
    const auto cell = [](const json& meta) {
        return position_cell({{"index", 3}, {"kind", "photo"}, {"meta", meta}});
    };
    EXPECT_EQ(cell({{"lat", 47.5}}), "47.5,?");
    EXPECT_EQ(cell({{"lat", 47.5}, {"lon", "east"}}), "47.5,\"east\"");
    EXPECT_EQ(cell({{"lat", 47.5}, {"lon", nullptr}}), "47.5,?");
    EXPECT_EQ(cell({{"lat", 47.5}, {"lon", {1, 2}}}), "47.5,[1,2]");
    EXPECT_EQ(cell({{"lon", 8.5}, {"alt_m", true}}), "?,8.5 truem");
    const auto row = capture_table_row(crafted_capture());
    EXPECT_TRUE(terminal_safe(row)) << row;
    EXPECT_NE(row.find(R"x("=HYPERLINK(\"x\")",8.5 "@SUM(1)"m)x"), std::string::npos) << row;
    const auto hostile = capture_table_row({{"meta", {{"lat", "\x1b[2J\n"}, {"lon", 1}}}});
    EXPECT_TRUE(terminal_safe(hostile)) << hostile;
    EXPECT_NE(hostile.find(R"("\u001b[2J\n",1)"), std::string::npos) << hostile;
}

TEST(CapturesPage, MoreNextAndAnOlderGportd) {
    const json two = json::array({{{"index", 5}}, {{"index", 6}}});
    const auto bounded = read_captures_page({{"captures", two}, {"next", 7}, {"more", true}}, 5);
    EXPECT_EQ(bounded.captures.size(), 2u);
    EXPECT_EQ(bounded.next, 7u);
    EXPECT_TRUE(bounded.more);
    EXPECT_FALSE(read_captures_page({{"captures", two}, {"next", 7}, {"more", false}}, 5).more);
    EXPECT_TRUE(read_captures_page({{"captures", two}, {"next", 7}}, 5).more)
        << "no `more`: go on while pages come";
    EXPECT_FALSE(read_captures_page({{"captures", json::array()}, {"next", 7}}, 5).more);
    EXPECT_FALSE(read_captures_page({{"captures", two}, {"next", 5}, {"more", true}}, 5).more)
        << "a next that does not advance ends the listing";
    const auto junk = read_captures_page({{"captures", "x"}, {"next", "y"}, {"more", 1}}, 3);
    EXPECT_TRUE(junk.captures.empty());
    EXPECT_EQ(junk.next, 3u);
    EXPECT_FALSE(junk.more);
    EXPECT_FALSE(capture_index({{"index", -1}}));
    EXPECT_EQ(capture_index({{"index", 4}}), 4u);
}

}  // namespace
}  // namespace gport::cli::printable_test
