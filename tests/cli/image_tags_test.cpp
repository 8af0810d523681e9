// gportctl geotag's pure part: the camera's time, matching, the tags and
// OpenDroneMap's geo.txt (cli/src/image_tags.hpp).
#include "image_tags.hpp"

#include <gtest/gtest.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <limits>

#include "clock_offset.hpp"

namespace gport::cli {
namespace {

using nlohmann::json;

constexpr std::int64_t kT = 1795762800;  // 2026-11-27 07:00:00 UTC

TEST(ImageTime, LocalTimeWithItsOffsetOrTheClockOffsetAndSubseconds) {
    const auto with_offset = image_file(json{{"SourceFile", "/d/A.JPG"},
                                             {"DateTimeOriginal", "2026:11:27 08:00:00"},
                                             {"SubSecTimeOriginal", "25"},
                                             {"OffsetTimeOriginal", "+01:00"}},
                                        -7200);  // the file's own offset wins over --clock-offset
    ASSERT_TRUE(with_offset.utc_us);
    EXPECT_EQ(*with_offset.utc_us, kT * 1000000 + 250000);
    const auto by_clock = image_file(json{{"SourceFile", "/d/B.JPG"},
                                          {"DateTimeOriginal", "2026:11:27 01:30:00"},
                                          {"SubSecTimeOriginal", 5}},
                                     -19800);  // a camera set to UTC-05:30
    ASSERT_TRUE(by_clock.utc_us);
    EXPECT_EQ(*by_clock.utc_us, kT * 1000000 + 500000);
    for (const char* bad :
         {"", "2026-11-27 07:00:00", "2026:13:27 07:00:00", "0000:00:00 00:00:00",
          "2026:11:27 07:00:00 trailing", "2026:02:30 07:00:00", "2026:11:27 -1:00:00"}) {
        EXPECT_FALSE(
            image_file(json{{"SourceFile", "/d/C.JPG"}, {"DateTimeOriginal", bad}}, 0).utc_us)
            << bad;
    }
    EXPECT_FALSE(image_file(json{{"SourceFile", "/d/D.JPG"}}, 0).utc_us) << "no time at all";
    // Past a 32-bit time_t's end (Debian 12's armhf), the same on every target.
    const auto later = image_file(
        json{{"SourceFile", "/d/E.JPG"}, {"DateTimeOriginal", "2040:01:01 00:00:00"}}, 0);
    ASSERT_TRUE(later.utc_us);
    EXPECT_EQ(*later.utc_us, 2208988800LL * 1000000);
}

PhotoCapture capture_at(std::uint64_t index, std::int64_t utc_s) {
    PhotoCapture c;
    c.index = index;
    c.utc_us = utc_s * 1000000;
    return c;
}

ImageFile image_at(const std::string& path, std::optional<std::int64_t> utc_s) {
    ImageFile f;
    f.path = path;
    if (utc_s) {
        f.utc_us = *utc_s * 1000000;
    }
    return f;
}

TEST(MatchByTime, ClosestFirstOneToOneWithinTheTolerance) {
    // Two images near capture 2: the closer one takes it; the other falls
    // back to nothing (capture 1 is 3 s away, beyond 2 s).
    const std::vector<PhotoCapture> captures{capture_at(1, kT), capture_at(2, kT + 3),
                                             capture_at(3, kT + 10)};
    const std::vector<ImageFile> images{image_at("a", kT + 3), image_at("b", kT + 4),
                                        image_at("c", kT + 11), image_at("d", std::nullopt)};
    const auto m = match_by_time(images, captures, 2000000);
    ASSERT_EQ(m.matched.size(), 2U);
    EXPECT_EQ(m.matched[0].image, 0U);
    EXPECT_EQ(m.matched[0].capture, 1U);
    EXPECT_EQ(m.matched[0].delta_us, 0);
    EXPECT_EQ(m.matched[1].image, 2U);
    EXPECT_EQ(m.matched[1].capture, 2U);
    EXPECT_EQ(m.matched[1].delta_us, 1000000);
    EXPECT_EQ(m.images_left, (std::vector<std::size_t>{1, 3}));
    EXPECT_EQ(m.captures_left, (std::vector<std::size_t>{0}));
}

TEST(MatchInOrder, OldestImageToLowestIndexAndTheRestReported) {
    const std::vector<PhotoCapture> captures{capture_at(7, kT), capture_at(5, kT)};
    const std::vector<ImageFile> images{image_at("IMG_2.JPG", kT + 9),
                                        image_at("IMG_1.JPG", kT + 9),
                                        image_at("IMG_0.JPG", kT + 1)};
    const auto m = match_in_order(images, captures);
    ASSERT_EQ(m.matched.size(), 2U);
    EXPECT_EQ(m.matched[0].image, 2U) << "the oldest image";
    EXPECT_EQ(m.matched[0].capture, 1U) << "capture 5";
    EXPECT_EQ(m.matched[1].image, 1U) << "same time: by name";
    EXPECT_EQ(m.matched[1].capture, 0U) << "capture 7";
    EXPECT_EQ(m.images_left, (std::vector<std::size_t>{0}));
    EXPECT_TRUE(m.captures_left.empty());
}

TEST(PhotoCapture, PositionAnglesAndYawOnlyWithAHeading) {
    const json capture = json::parse(R"({"index":12,"kind":"photo","utc_us":1795762800000000,
        "attitude":{"imu":{"roll":0.12,"pitch":-30.05,"yaw":12.5},"hall":{"roll":0.1,"pitch":-29.98,"yaw":45.01},"age_ms":7},
        "meta":{"lat":-35.363261,"lon":149.1652299,"alt_m":584.09}})");
    const auto p = photo_capture(capture);
    ASSERT_TRUE(p);
    EXPECT_EQ(p->index, 12U);
    EXPECT_EQ(p->pitch, -30.05);
    EXPECT_EQ(p->roll, 0.12);
    EXPECT_FALSE(p->yaw) << "the hall yaw is relative to the vehicle: no heading, no yaw";
    EXPECT_EQ(
        tag_arguments(*p),
        (std::vector<std::string>{
            "-GPSLatitude=-35.3632610", "-GPSLatitudeRef=-35.3632610", "-GPSLongitude=149.1652299",
            "-GPSLongitudeRef=149.1652299", "-GPSAltitude=584.090", "-GPSAltitudeRef=584.090",
            "-XMP-drone-dji:GimbalPitchDegree=-30.05", "-XMP-drone-dji:GimbalRollDegree=0.12"}));
    auto with_heading = capture;
    with_heading["meta"]["heading_deg"] = 350;
    EXPECT_NEAR(*photo_capture(with_heading)->yaw, 35.01, 1e-9) << "350 + 45.01, wrapped";
    auto record = capture;
    record["kind"] = "record_start";
    EXPECT_FALSE(photo_capture(record)) << "only photos";
    auto half = capture;
    half["meta"].erase("lon");
    EXPECT_FALSE(photo_capture(half)->lat) << "half a position is none";
    EXPECT_FALSE(photo_capture(json::parse(R"({"index":-1,"kind":"photo","utc_us":1})")));
}

// gportd's stamp (issue 43) wins over the meta: its position, its accuracy,
// the heading at the shutter and the autopilot's UTC, by which the images
// are matched; an untagged capture gets no position, whatever the meta says.
TEST(PhotoCapture, GportdsStampWinsOverTheMetaAndUntaggedMeansNoPosition) {
    const json capture = json::parse(R"({"index":3,"kind":"photo","utc_us":1795762800000000,
        "attitude":{"imu":{"roll":0.5,"pitch":-90,"yaw":0},"hall":{"roll":0,"pitch":-90,"yaw":-20},"age_ms":3},
        "meta":{"lat":1.0,"lon":2.0,"alt_m":3.0,"heading_deg":0},
        "vehicle":{"tagged":true,"utc_us":1795910400250000,"lat":47.397742,"lon":8.545594,
          "alt_msl_m":488.5,"alt_rel_m":40.0,"velocity_ned":[15,0,0],"heading_deg":10,
          "h_acc_m":1.25,"v_acc_m":2.5,"fix":3,"satellites":12,"age_ms":130}})");
    const auto p = photo_capture(capture);
    ASSERT_TRUE(p);
    EXPECT_EQ(p->lat, 47.397742);
    EXPECT_EQ(p->alt_m, 488.5);
    EXPECT_EQ(p->utc_us, 1795910400250000) << "matched by the autopilot's UTC";
    EXPECT_NEAR(*p->yaw, -10.0, 1e-9) << "the vehicle's heading 10 + the hall yaw -20";
    const auto args = tag_arguments(*p);
    for (const auto* expected :
         {"-GPSLatitude=47.3977420", "-GPSImgDirection=350.00", "-GPSImgDirectionRef=T",
          "-XMP-Camera:GPSXYAccuracy=1.250", "-XMP-Camera:GPSZAccuracy=2.500",
          "-GPSDateStamp=2026:11:29", "-GPSTimeStamp=00:00:00.250000"}) {
        EXPECT_NE(std::find(args.begin(), args.end(), expected), args.end()) << expected;
    }

    auto untagged = capture;
    untagged["vehicle"] = json::parse(
        R"j({"tagged":false,"utc_us":1795910400250000,"why":"no 3D GPS fix (GPS_FIX_TYPE 1)"})j");
    const auto u = photo_capture(untagged);
    ASSERT_TRUE(u);
    EXPECT_FALSE(u->lat) << "never the meta's position when gportd said untagged";
    EXPECT_EQ(u->untagged, "no 3D GPS fix (GPS_FIX_TYPE 1)");
    EXPECT_FALSE(u->yaw);
    auto in_2040 = capture;
    in_2040["vehicle"]["utc_us"] = 2208988800LL * 1000000 + 500000;
    const auto args_2040 = tag_arguments(*photo_capture(in_2040));
    EXPECT_NE(std::find(args_2040.begin(), args_2040.end(), "-GPSDateStamp=2040:01:01"),
              args_2040.end());
    EXPECT_NE(std::find(args_2040.begin(), args_2040.end(), "-GPSTimeStamp=00:00:00.500000"),
              args_2040.end());
    auto in_far_future = capture;
    in_far_future["vehicle"]["utc_us"] = std::numeric_limits<std::int64_t>::max();
    const auto args_far = tag_arguments(*photo_capture(in_far_future));
    EXPECT_TRUE(std::none_of(args_far.begin(), args_far.end(), [](const std::string& a) {
        return a.starts_with("-GPSDateStamp");
    })) << "a year of more than four digits is no EXIF date";

    const auto bare = tag_arguments(*u);
    EXPECT_TRUE(std::none_of(bare.begin(), bare.end(), [](const std::string& a) {
        return a.starts_with("-GPS") || a.starts_with("-XMP-Camera");
    }));
}

TEST(GeoTxt, NineColumnsWhenTheAccuracyIsKnown) {
    PhotoCapture a = capture_at(1, kT);
    a.lat = 47.397742;
    a.lon = 8.545594;
    a.alt_m = 488.5;
    a.yaw = 12.5;
    a.pitch = -90;
    a.h_acc_m = 1.25;
    a.v_acc_m = 2.5;
    const std::vector<ImageFile> images{image_at("/d/IMG_1.JPG", kT)};
    const auto m = match_by_time(images, {a}, 1000000);
    EXPECT_EQ(geo_txt(images, {a}, m),
              "EPSG:4326\nIMG_1.JPG 8.5455940 47.3977420 488.500 12.50 -90.00 0.00 1.250 2.500\n");
}

TEST(GeoTxt, Epsg4326ThenNameLonLatAltAndAnglesZeroWhenUnknown) {
    PhotoCapture a = capture_at(1, kT);
    a.lat = 47.397742;
    a.lon = 8.545594;
    a.alt_m = 488.5;
    a.pitch = -90;
    PhotoCapture b = capture_at(2, kT + 5);  // no position: not listed
    const std::vector<ImageFile> images{image_at("/d/IMG_1.JPG", kT),
                                        image_at("/d/IMG_2.JPG", kT + 5)};
    const auto m = match_by_time(images, {a, b}, 1000000);
    EXPECT_EQ(geo_txt(images, {a, b}, m),
              "EPSG:4326\nIMG_1.JPG 8.5455940 47.3977420 488.500 0.00 -90.00 0.00\n");
}

TEST(EstimateOffset, TheOffsetThatPairsTheMostAndARivalThatPairsAsMany) {
    std::vector<PhotoCapture> captures;
    std::vector<ImageFile> images;
    for (int k = 0; k < 20; ++k) {  // a photo every 2 s, the camera 31 s ahead
        captures.push_back(capture_at(static_cast<std::uint64_t>(k), kT + 2 * k));
        images.push_back(image_at("i" + std::to_string(k), kT + 2 * k + 31));
    }
    const auto e = estimate_offset(images, captures, 3600000000, 500000);
    EXPECT_EQ(e.offset_us, 31000000);
    EXPECT_EQ(e.pairs, 20U);
    EXPECT_EQ(e.pairs_at_given, 0U);
    EXPECT_FALSE(e.rival_us) << "+29 s and +33 s pair 19";

    const auto ambiguous =
        estimate_offset({image_at("a", kT), image_at("b", kT + 10), image_at("c", kT + 20)},
                        {capture_at(1, kT), capture_at(2, kT + 10)}, 3600000000, 500000);
    EXPECT_EQ(ambiguous.offset_us, 0) << "the given offset wins a tie";
    EXPECT_EQ(ambiguous.pairs, 2U);
    EXPECT_EQ(ambiguous.rival_us, 10000000);

    const auto none =
        estimate_offset({image_at("a", kT + 100)}, {capture_at(1, kT)}, 2000000, 500000);
    EXPECT_EQ(none.pairs, 0U) << "nothing within the search";
}

TEST(HourShift, TheWholeHoursThatBringTheMostMissesToACapture) {
    const std::vector<PhotoCapture> captures{capture_at(1, kT), capture_at(2, kT + 5)};
    const std::vector<ImageFile> images{image_at("a", kT - 7200), image_at("b", kT + 5 - 7200),
                                        image_at("c", kT + 999)};
    const auto shift = hour_shift(images, {0, 1, 2}, captures, 1000000);
    ASSERT_TRUE(shift);
    EXPECT_EQ(shift->hours, -2);
    EXPECT_EQ(shift->images, 2U);
    EXPECT_FALSE(hour_shift(images, {2}, captures, 1000000));
}

// 10,000 images and 4,096 captures all within --tolerance 1h of each other:
// the estimate and the matching never hold every pair (41 million), so this
// stays in megabytes and seconds. No wall-clock assertion; the peak resident
// size is printed and bounded loosely.
TEST(MatchByTime, TenThousandImagesAndFourThousandCapturesInASweep) {
    std::vector<PhotoCapture> captures;
    std::vector<ImageFile> images;
    for (int k = 0; k < 4096; ++k) {
        captures.push_back(capture_at(static_cast<std::uint64_t>(k), 0));
        captures.back().utc_us = kT * 1000000 + std::int64_t{k} * 700000;  // every 0.7 s
    }
    for (int k = 0; k < 10000; ++k) {
        images.push_back(image_at("i" + std::to_string(k), std::nullopt));
        images.back().utc_us = kT * 1000000 + std::int64_t{k} * 287000 + 42000;
    }
    const auto start = std::chrono::steady_clock::now();
    const auto e = estimate_offset(images, captures, 3600000000, 500000);
    const auto m = match_by_time(images, captures, 3600000000);
    const auto seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    rusage usage{};
    ::getrusage(RUSAGE_SELF, &usage);
    std::printf("10000 x 4096 at 1h: %.2f s, peak RSS %ld MB (the whole test binary)\n", seconds,
                usage.ru_maxrss / 1024);
    EXPECT_GT(e.pairs, 4000U);
    EXPECT_EQ(m.matched.size(), 4096U);
    EXPECT_EQ(m.images_left.size(), 10000U - 4096U);
    EXPECT_LT(usage.ru_maxrss / 1024, 400) << "MB: no pair list of 41 million";
}

}  // namespace
}  // namespace gport::cli
