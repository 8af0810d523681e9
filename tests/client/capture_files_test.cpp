// The capture log's one writer (gport/client/capture_files.hpp), through the
// installed interface: the CSV against RFC 4180 (every field quoted, quotes
// doubled, no line break or control inside a row), its text field defused,
// its numbers as JSON writes them, times before 1970 and at the ends of
// int64, a capture missing anything, and the GeoJSON beside it.
#include "gport/client/capture_files.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gport/client/printable.hpp"
#include "rfc4180.hpp"

namespace gport::client {
namespace {

using nlohmann::json;
using testing::quoted_csv_fields;

// The row's fields, read back strictly; the row must end in its one "\n".
std::vector<std::string> fields_of(const std::string& row) {
    EXPECT_TRUE(row.ends_with("\n")) << row;
    const auto line = row.substr(0, row.size() - 1);
    EXPECT_EQ(line.find_first_of("\r\n"), std::string::npos) << row;
    const auto fields = quoted_csv_fields(line);
    EXPECT_TRUE(fields) << "not RFC 4180 with every field quoted: " << row;
    EXPECT_EQ(fields.value_or(std::vector<std::string>{}).size(), 20U) << row;
    return fields.value_or(std::vector<std::string>(20));
}

std::string row_of(const json& capture) {
    return capture_csv_row(capture.dump());
}

std::string kind_cell(const json& kind) {
    return fields_of(row_of({{"index", 1}, {"kind", kind}}))[2];
}

std::string utc_cell(const json& utc_us) {
    return fields_of(row_of({{"index", 1}, {"utc_us", utc_us}}))[1];
}

const json kCapture = {
    {"index", 12},
    {"kind", "photo"},
    {"utc_us", 1795563183085470},
    {"attitude",
     {{"imu", {{"roll", 0.5}, {"pitch", -30.25}, {"yaw", 120}}},
      {"hall", {{"roll", 0.0}, {"pitch", -30}, {"yaw", 119.75}}},
      {"age_ms", 3}}},
    {"meta", {{"lat", 47.397742}, {"lon", -8.545594}, {"alt_m", 488.2}, {"wp", 3}}},
    {"client", {{"pid", 40}, {"uid", 0}, {"name", "gport-mavlink"}}}};

TEST(CaptureCsv, TheHeaderNamesTheColumnsUnquoted) {
    EXPECT_EQ(captures_csv_header(),
              "index,utc,kind,imu_roll,imu_pitch,imu_yaw,hall_roll,hall_pitch,hall_yaw,lat,lon,"
              "alt_m,position,position_lat,position_lon,position_alt_m,h_acc_m,v_acc_m,heading_deg,"
              "gps_utc\n");
}

TEST(CaptureCsv, AWholeCaptureIsOneRowOfQuotedFields) {
    EXPECT_EQ(row_of(kCapture),
              R"("12","2026-11-24T23:33:03.085470Z","photo","0.5","-30.25","120","0.0","-30",)"
              R"("119.75","47.397742","-8.545594","488.2","meta","47.397742","-8.545594","488.2",)"
              R"("","","","")"
              "\n");
}

TEST(CaptureCsv, WhatIsMissingOrMistypedIsAnEmptyField) {
    const std::string empty = R"("","","","","","","","","","","","","","","","","","","","")"
                              "\n";
    EXPECT_EQ(capture_csv_row("{}"), empty);
    EXPECT_EQ(capture_csv_row("[1,2]"), empty);
    EXPECT_EQ(capture_csv_row("null"), empty);
    EXPECT_EQ(row_of({{"index", "12"},
                      {"utc_us", "now"},
                      {"kind", nullptr},
                      {"attitude", {{"imu", 5}, {"hall", {{"roll", true}}}}},
                      {"meta", "47,8"}}),
              empty);
    const auto no_lon = fields_of(row_of({{"meta", {{"lat", 47.5}, {"lon", "east"}}}}));
    EXPECT_EQ(no_lon[9], "47.5");
    EXPECT_EQ(no_lon[10], "") << "a string is no longitude";
    EXPECT_EQ(no_lon[11], "");
}

TEST(CaptureCsv, TextThatIsNotJsonIsABadReplyNamingIt) {
    for (const std::string text : {"", "{", "photo", "{\"kind\":\"\xff\"}"}) {
        try {
            capture_csv_row(text);
            ADD_FAILURE() << "no error for " << text;
        } catch (const Error& e) {
            EXPECT_TRUE(e.is(ErrorCode::kBadReply)) << e.what();
            EXPECT_NE(std::string(e.what()).find("capture: not JSON"), std::string::npos)
                << e.what();
        }
    }
}

TEST(CaptureCsv, QuotesAreDoubledAndCommasStayInTheirField) {
    const auto row = row_of({{"index", 1}, {"kind", "say \"cheese\", twice"}});
    EXPECT_NE(row.find(R"("say ""cheese"", twice")"), std::string::npos) << row;
    EXPECT_EQ(fields_of(row)[2], "say \"cheese\", twice");
    EXPECT_EQ(kind_cell("\""), "\"");
    EXPECT_EQ(kind_cell(","), ",");
}

TEST(CaptureCsv, LineBreaksAndControlsInTheTextAreShownNotWritten) {
    EXPECT_EQ(kind_cell("a\r\nb"), "a\\x0d\\x0ab");
    EXPECT_EQ(kind_cell("\x1b[2J\x07"), "\\x1b[2J\\x07");
    EXPECT_EQ(kind_cell("\x7f"), "\\x7f");
    EXPECT_EQ(kind_cell("\xc2\x9b"), "\\u009b") << "C1 CSI";
    EXPECT_EQ(kind_cell("\t=1"), "\\x09=1") << "escaped, so no formula";
}

TEST(CaptureCsv, ATextLeadThatASpreadsheetRunsGetsAQuote) {
    for (const std::string lead : {"=", "+", "-", "@"}) {
        EXPECT_EQ(kind_cell(lead + "cmd|'/C calc'!A0"), "'" + lead + "cmd|'/C calc'!A0");
    }
    EXPECT_EQ(kind_cell("record_start"), "record_start");
    EXPECT_EQ(kind_cell("'quoted"), "'quoted");
}

TEST(CaptureCsv, NonAsciiTextIsKept) {
    EXPECT_EQ(kind_cell("f\xc3\xbcr \xe5\x86\x99\xe7\x9c\x9f \xf0\x9f\x93\xb7"),
              "f\xc3\xbcr \xe5\x86\x99\xe7\x9c\x9f \xf0\x9f\x93\xb7");
    EXPECT_EQ(kind_cell("\xef\xbf\xbd"), "\xef\xbf\xbd") << "U+FFFD as gportd writes a bad byte";
}

TEST(CaptureCsv, AKindOfAnotherTypeIsItsJsonTextEscapedLikeAnyText) {
    EXPECT_EQ(kind_cell(42), "42");
    EXPECT_EQ(kind_cell(-42), "'-42");
    EXPECT_EQ(kind_cell({{"a", "\"\n"}}), "{\"a\":\"\\\"\\n\"}");
    const auto row = row_of({{"index", 1}, {"kind", {{"a", 1}}}});
    EXPECT_NE(row.find(R"("{""a"":1}")"), std::string::npos) << row;
}

TEST(CaptureCsv, NumbersAreWrittenAsJsonWritesThem) {
    const auto row = [](const json& meta) { return fields_of(row_of({{"meta", meta}})); };
    EXPECT_EQ(row({{"lat", -30.5}})[9], "-30.5") << "a sign stays: still a number";
    EXPECT_EQ(row({{"lat", 1e300}})[9], "1e+300");
    EXPECT_EQ(row({{"lat", -1e-7}})[9], "-1e-07");
    EXPECT_EQ(row({{"lat", 47}})[9], "47");
    EXPECT_EQ(row({{"lat", 47.0}})[9], "47.0");
    EXPECT_EQ(row({{"lat", 0.1}})[9], "0.1") << "shortest round trip";
    EXPECT_EQ(row({{"alt_m", "488"}})[11], "") << "a string is no number";
    EXPECT_EQ(row({{"alt_m", false}})[11], "");
    EXPECT_EQ(fields_of(capture_csv_row(R"({"index":18446744073709551615})"))[0],
              "18446744073709551615");
    EXPECT_EQ(fields_of(capture_csv_row(R"({"index":-3})"))[0], "-3");
}

TEST(CaptureCsv, TimesBefore1970AreCountedBackFromTheEpoch) {
    EXPECT_EQ(utc_cell(0), "1970-01-01T00:00:00.000000Z");
    EXPECT_EQ(utc_cell(-1), "1969-12-31T23:59:59.999999Z");
    EXPECT_EQ(utc_cell(-999999), "1969-12-31T23:59:59.000001Z");
    EXPECT_EQ(utc_cell(-1000000), "1969-12-31T23:59:59.000000Z");
    EXPECT_EQ(utc_cell(-1000001), "1969-12-31T23:59:58.999999Z");
    EXPECT_EQ(utc_cell(-86400000000LL - 500000), "1969-12-30T23:59:59.500000Z");
}

TEST(CaptureCsv, TimesAtTheEndsOfInt64AreWrittenAndPastThemLeftOut) {
    constexpr auto kMax = std::numeric_limits<std::int64_t>::max();
    constexpr auto kMin = std::numeric_limits<std::int64_t>::min();
    EXPECT_EQ(utc_cell(kMax), "294247-01-10T04:00:54.775807Z");
    EXPECT_EQ(utc_cell(kMin), "-290308-12-21T19:59:05.224192Z");
    EXPECT_EQ(utc_cell(std::uint64_t{kMax} + 1), "") << "no int64: no time";
    EXPECT_EQ(utc_cell(1.7955631830854e15), "") << "not an integer";
    EXPECT_EQ(utc_text(1795563183085470), "2026-11-24T23:33:03.085470Z");
    // Past a 32-bit time_t's end (Debian 12's armhf): the same text there.
    EXPECT_EQ(utc_text(2147483648LL * 1000000 + 5), "2038-01-19T03:14:08.000005Z");
    EXPECT_EQ(utc_text(-1), "1969-12-31T23:59:59.999999Z");
}

TEST(CaptureGeoJson, AFeatureIsAPointAtLonLatAlt) {
    const auto feature = json::parse(capture_geojson_feature(kCapture.dump()));
    EXPECT_EQ(feature.at("type"), "Feature");
    EXPECT_EQ(feature.at("geometry"),
              json({{"type", "Point"}, {"coordinates", {-8.545594, 47.397742, 488.2}}}));
    const auto& properties = feature.at("properties");
    EXPECT_EQ(properties.at("index"), 12);
    EXPECT_EQ(properties.at("utc"), "2026-11-24T23:33:03.085470Z");
    EXPECT_EQ(properties.at("kind"), "photo");
    EXPECT_EQ(properties.at("attitude"), kCapture.at("attitude"));
}

TEST(CaptureGeoJson, OnlyANumericLatAndLonMakeAPoint) {
    const auto feature = [](const json& capture) {
        return capture_geojson_feature(capture.dump());
    };
    EXPECT_EQ(feature({{"meta", {{"lat", 47.5}, {"lon", "east"}}}}), "");
    EXPECT_EQ(feature({{"meta", {{"lat", 47.5}}}}), "");
    EXPECT_EQ(feature({{"index", 1}}), "");
    EXPECT_EQ(capture_geojson_feature("[]"), "");
    const auto flat =
        json::parse(feature({{"meta", {{"lat", -33.9}, {"lon", 151.2}, {"alt_m", "high"}}},
                             {"utc_us", -1},
                             {"kind", "=x\n"}}));
    EXPECT_EQ(flat.at("geometry").at("coordinates"), json({151.2, -33.9}));
    EXPECT_EQ(flat.at("properties").at("utc"), "1969-12-31T23:59:59.999999Z");
    EXPECT_EQ(flat.at("properties").at("kind"), "=x\n") << "JSON escapes it itself";
    const auto untimed = json::parse(feature({{"meta", {{"lat", 1}, {"lon", 2}}}}));
    EXPECT_TRUE(untimed.at("properties").at("utc").is_null());
    EXPECT_THROW(capture_geojson_feature("{"), Error);
}

TEST(CaptureGeoJson, HeadFeaturesAndTailAreOneCollection) {
    const auto text = captures_geojson_head() + capture_geojson_feature(kCapture.dump()) + "," +
                      capture_geojson_feature(json({{"meta", {{"lat", 1}, {"lon", 2}}}}).dump()) +
                      captures_geojson_tail();
    EXPECT_TRUE(text.ends_with("]}\n"));
    const auto collection = json::parse(text);
    EXPECT_EQ(collection.at("type"), "FeatureCollection");
    EXPECT_EQ(collection.at("features").size(), 2U);
    EXPECT_TRUE(
        json::parse(captures_geojson_head() + captures_geojson_tail()).at("features").empty());
}

// gportd's stamp of a capture with meta (the caller's own, older position).
json stamped(const json& vehicle) {
    auto capture = kCapture;
    capture["vehicle"] = vehicle;
    return capture;
}

const json kTagged = {{"tagged", true}, {"utc_us", 1795563183012345}, {"lat", 47.3978},
                      {"lon", -8.5456}, {"alt_msl_m", 500.25},        {"h_acc_m", 0.9},
                      {"v_acc_m", 1.4}, {"heading_deg", 91.5},        {"age_ms", 120}};

TEST(CapturePosition, GportdsStampWinsOverTheMeta) {
    const auto p = capture_position(stamped(kTagged).dump());
    EXPECT_EQ(p.from, "vehicle");
    EXPECT_EQ(p.lat, 47.3978);
    EXPECT_EQ(p.lon, -8.5456);
    EXPECT_EQ(p.alt_m, 500.25);
    EXPECT_EQ(p.h_acc_m, 0.9);
    EXPECT_EQ(p.v_acc_m, 1.4);
    EXPECT_EQ(p.heading_deg, 91.5);
    EXPECT_EQ(p.gps_utc_us, 1795563183012345);
    const auto row = fields_of(row_of(stamped(kTagged)));
    EXPECT_EQ(row[9], "47.397742") << "the meta's own columns stay the meta's";
    EXPECT_EQ(std::vector<std::string>(row.begin() + 12, row.end()),
              (std::vector<std::string>{"vehicle", "47.3978", "-8.5456", "500.25", "0.9", "1.4",
                                        "91.5", "2026-11-24T23:33:03.012345Z"}));
    const auto feature = json::parse(capture_geojson_feature(stamped(kTagged).dump()));
    EXPECT_EQ(feature.at("geometry").at("coordinates"), json({-8.5456, 47.3978, 500.25}));
    EXPECT_EQ(feature.at("properties").at("position"), "vehicle");
    EXPECT_EQ(feature.at("properties").at("h_acc_m"), 0.9);
    EXPECT_EQ(feature.at("properties").at("gps_utc"), "2026-11-24T23:33:03.012345Z");
}

TEST(CapturePosition, UntaggedByGportdIsNoPositionNeverTheMetas) {
    const json untagged = {
        {"tagged", false}, {"why", "position 1500 ms old"}, {"utc_us", 1795563183012345}};
    const auto p = capture_position(stamped(untagged).dump());
    EXPECT_EQ(p.from, "");
    EXPECT_FALSE(p.lat);
    EXPECT_EQ(p.untagged, "position 1500 ms old");
    EXPECT_EQ(p.gps_utc_us, 1795563183012345) << "its true time is still known";
    const auto row = fields_of(row_of(stamped(untagged)));
    EXPECT_EQ(row[12], "untagged: position 1500 ms old");
    EXPECT_EQ(row[13], "");
    EXPECT_EQ(row[19], "2026-11-24T23:33:03.012345Z");
    EXPECT_EQ(capture_geojson_feature(stamped(untagged).dump()), "")
        << "no point on the map from a stale or absent position";
    // gportd's reason is text from the log: shown as gportctl shows text
    // from others, never a control byte in the file.
    const json hostile = {{"tagged", false}, {"why", "\x1b[2J\r\n=cmd"}};
    EXPECT_EQ(fields_of(row_of(stamped(hostile)))[12], "untagged: \\x1b[2J\\x0d\\x0a=cmd");
    EXPECT_EQ(capture_position(stamped({{"tagged", "yes"}}).dump()).untagged, "untagged by gportd");
}

TEST(CapturePosition, WithoutAVehicleTheMetaAsBeforeAndNoHalfPositions) {
    EXPECT_EQ(capture_position(kCapture.dump()).from, "meta");
    EXPECT_EQ(capture_position(stamped(nullptr).dump()).from, "meta");
    EXPECT_EQ(capture_position(kCapture.dump()).alt_m, 488.2);
    EXPECT_FALSE(capture_position(kCapture.dump()).h_acc_m) << "a caller's meta has no accuracy";
    auto beyond = kTagged;
    beyond["lat"] = 91;
    EXPECT_EQ(capture_position(stamped(beyond).dump()).from, "");
    auto half = kTagged;
    half.erase("lon");
    EXPECT_EQ(capture_position(stamped(half).dump()).from, "");
    EXPECT_EQ(capture_position(R"({"meta":{"lat":47.3}})").from, "");
    EXPECT_EQ(capture_position("{}").from, "");
    EXPECT_THROW(capture_position("{"), Error);
}

TEST(Printable, ControlsAndBadBytesAreShownAndTheRestKept) {
    EXPECT_EQ(printable("a\x1b[31mb\n"), "a\\x1b[31mb\\x0a");
    EXPECT_EQ(printable("\xc2\x9b\xff\xc0\xaf"), "\\u009b\\xff\\xc0\\xaf");
    EXPECT_EQ(printable("f\xc3\xbcr \\ \xf0\x9f\x93\xb7"), "f\xc3\xbcr \\ \xf0\x9f\x93\xb7");
    EXPECT_EQ(printable(std::string("a\0b", 3)), "a\\x00b");
}

}  // namespace
}  // namespace gport::client
