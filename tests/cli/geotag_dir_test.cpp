// gportctl geotag DIR through the whole of gportctl (issue 41): real JPEG
// files whose times exiftool writes, captures from a capture log file (no
// gportd asked); what matches, what is refused, what is written, the exit
// status.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include "gport/base/exit_status.hpp"
#include "gport/cli/run.hpp"
#include "minimal_jpeg.hpp"

namespace gport::cli::geotag_dir_test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using ::testing::HasSubstr;
using ::testing::Not;

constexpr std::int64_t kT = 1795762800;  // 2026-11-27 07:00:00 UTC

// EXIF's "YYYY:MM:DD HH:MM:SS" of a camera clock reading `camera_s`.
std::string exif_time(std::int64_t camera_s) {
    const auto t = static_cast<std::time_t>(camera_s);
    std::tm tm{};
    ::gmtime_r(&t, &tm);
    char text[32];
    std::strftime(text, sizeof text, "%Y:%m:%d %H:%M:%S", &tm);
    return text;
}

struct Ran {
    int status;
    std::string out;
    std::string err;
};

struct Image {
    std::string name;
    std::optional<std::int64_t> camera_s;  // the camera's clock; none: no DateTimeOriginal
};

class GeotagDir : public ::testing::Test {
  protected:
    void SetUp() override {
        const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
        root_ = fs::path(::testing::TempDir()) /
                ("gportctl-geotag-" + std::string(test->name()) + "-" + std::to_string(::getpid()));
        fs::remove_all(root_);
        fs::create_directories(root_ / "card");
    }
    void TearDown() override { fs::remove_all(root_); }

    // `n` photo captures, index 1.., `step_s` apart from kT; with a position
    // (lat = 10 + index / 1000) or without; each with the IMU's pitch.
    void captures(int n, std::int64_t step_s, bool position = true) {
        std::ofstream file(root_ / "captures.jsonl");
        for (int k = 1; k <= n; ++k) {
            json c = {{"index", k},
                      {"kind", "photo"},
                      {"utc_us", (kT + (k - 1) * step_s) * 1000000},
                      {"attitude", {{"imu", {{"pitch", -30.0}, {"roll", 0.0}}}}},
                      {"meta", json::object()}};
            if (position) {
                c["meta"] = {{"lat", 10.0 + k / 1000.0}, {"lon", 20.0}};
            }
            file << c.dump() << "\n";
        }
    }

    // The files, then their times in one exiftool run.
    void images(const std::vector<Image>& list) {
        std::ofstream args(root_ / "args");
        bool first = true;
        for (const auto& image : list) {
            std::ofstream(card() + "/" + image.name, std::ios::binary)
                << gport::testing::minimal_jpeg();
            if (!image.camera_s) {
                continue;
            }
            if (!first) {
                args << "-execute\n";
            }
            first = false;
            args << "-DateTimeOriginal=" << exif_time(*image.camera_s) << "\n"
                 << card() << "/" << image.name << "\n";
        }
        args.close();
        const auto command = "exiftool -q -q -overwrite_original -@ '" + (root_ / "args").string() +
                             "' -common_args -q -q";
        ASSERT_EQ(std::system(command.c_str()), 0) << "exiftool (libimage-exiftool-perl)";
    }

    // IMG_01.JPG... taken at the captures' times (every `step_s` from kT)
    // by a camera `ahead_s` ahead.
    void images_every(int n, std::int64_t step_s, std::int64_t ahead_s) {
        std::vector<Image> list;
        for (int k = 1; k <= n; ++k) {
            list.push_back({name(k), kT + (k - 1) * step_s + ahead_s});
        }
        images(list);
    }

    static std::string name(int k) {
        return "IMG_" + std::string(k < 10 ? "0" : "") + std::to_string(k) + ".JPG";
    }

    Ran geotag(std::vector<std::string> args) {
        args.insert(args.begin(), {"--socket", "/nonexistent/gportd.sock", "geotag", card(),
                                   "--captures", (root_ / "captures.jsonl").string()});
        std::ostringstream out;
        std::ostringstream err;
        const int status = main_with(args, nullptr, out, err, [] { return false; }, {});
        return {status, out.str(), err.str()};
    }

    std::string card() const { return (root_ / "card").string(); }

    // The GPSLatitude exiftool reads from a file, if any.
    std::optional<double> latitude(const std::string& file) {
        const auto out = root_ / "tags.json";
        const auto command = "exiftool -json -n -GPSLatitude '" + card() + "/" + file + "' > '" +
                             out.string() + "' 2>/dev/null";
        if (std::system(command.c_str()) != 0) {
            return std::nullopt;
        }
        const auto j = json::parse(std::ifstream(out), nullptr, false);
        if (!j.is_array() || j.empty() || !j[0].contains("GPSLatitude")) {
            return std::nullopt;
        }
        return j[0]["GPSLatitude"].get<double>();
    }

    fs::path root_;
};

TEST_F(GeotagDir, ACameraClockAheadIsRefusedNamingTheOffsetItPairsAt) {
    captures(20, 2);
    images_every(20, 2, 31);  // no OffsetTimeOriginal, the clock 31 s ahead
    const auto refused = geotag({"--tolerance", "1h"});
    EXPECT_EQ(refused.status, kExitFailure) << refused.out;
    EXPECT_THAT(refused.err, HasSubstr("camera's clock is +31.0 s off UTC (20 of 20 images"));
    EXPECT_THAT(refused.err, HasSubstr("pass --clock-offset 31.0 to use it"));
    EXPECT_THAT(refused.out, Not(HasSubstr("  capture "))) << "no pairing reported as if right";

    const auto accepted = geotag({"--tolerance", "1h", "--clock-offset", "31"});
    EXPECT_EQ(accepted.status, kExitOk) << accepted.out << accepted.err;
    for (int k = 1; k <= 20; ++k) {
        EXPECT_THAT(accepted.out,
                    HasSubstr(name(k) + "  capture " + std::to_string(k) + "  +0.00 s"));
    }
    EXPECT_THAT(accepted.out,
                HasSubstr("camera clock: UTC+31.0 s by the images (20 of 20 within 0.5 s"));

    const auto forced = geotag({"--tolerance", "1h", "--force"});
    EXPECT_THAT(forced.err, HasSubstr("--force: the images pair best"));
    EXPECT_THAT(forced.out, HasSubstr("20 of 20 images matched by time")) << "at the given offset";
}

TEST_F(GeotagDir, TwoOffsetsThatPairAsWellAreAmbiguous) {
    captures(2, 10);
    images_every(3, 10, 0);  // three images, two captures: +0 s and +10 s pair two each
    const auto r = geotag({"--tolerance", "1h"});
    EXPECT_EQ(r.status, kExitFailure);
    EXPECT_THAT(r.err, HasSubstr("the images pair as well with the camera's clock at +0.0 s as at "
                                 "+10.0 s (2 of 3 images): ambiguous"));
    EXPECT_THAT(r.out, Not(HasSubstr("matched")));
}

TEST_F(GeotagDir, InOrderRefusesAMissedShotNamingTheCounts) {
    captures(20, 2);
    std::vector<Image> list;
    for (int k = 1; k <= 20; ++k) {
        if (k != 5) {  // the camera skipped the fifth shot; its clock was never set
            list.push_back({name(k), kT + 86400 + (k - 1) * 2});
        }
    }
    images(list);
    const auto r = geotag({"--in-order", "--write"});
    EXPECT_EQ(r.status, kExitFailure) << r.out;
    EXPECT_THAT(r.err, HasSubstr("--in-order needs as many images as photo captures: 19 images, "
                                 "20 captures"));
    EXPECT_FALSE(latitude(name(6))) << "nothing written";
}

TEST_F(GeotagDir, InOrderRefusesImagesWithoutATimeNamingThem) {
    captures(20, 2);
    std::vector<Image> list;
    for (int k = 1; k <= 20; ++k) {
        list.push_back({name(k), k == 13 ? std::nullopt : std::optional(kT + 86400 + k * 2)});
    }
    images(list);
    const auto r = geotag({"--in-order"});
    EXPECT_EQ(r.status, kExitFailure) << r.out;
    EXPECT_THAT(r.err, HasSubstr("and 1 of 20 have none: IMG_13.JPG"));
}

TEST_F(GeotagDir, AnImageThatGetsNoPositionIsAFailureNamedEvenWhenWritten) {
    captures(12, 2, /*position=*/false);
    images_every(12, 2, 0);
    const auto r = geotag({"--write"});
    EXPECT_EQ(r.status, kExitFailure) << r.out;
    EXPECT_THAT(r.err, HasSubstr("12 images matched a capture with no position (none in its meta, "
                                 "or gportd marked it untagged: no fit position at the shutter) "
                                 "and get none: IMG_01.JPG, IMG_02.JPG"));
    EXPECT_THAT(r.out, HasSubstr("wrote 12 of 12 images")) << "the angles";
}

TEST_F(GeotagDir, AFileExiftoolCannotWriteIsNamedAndTheOthersWritten) {
    captures(3, 2);
    images_every(3, 2, 0);
    {  // IMG_02.JPG loses its end: exiftool reads its time, cannot write it
        const auto path = card() + "/" + name(2);
        std::ifstream in(path, std::ios::binary);
        std::string bytes((std::istreambuf_iterator<char>(in)), {});
        bytes.resize(bytes.rfind("\xFF\xDA") + 4);
        std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
    }
    const auto r = geotag({"--write"});
    EXPECT_EQ(r.status, kExitFailure) << r.out;
    EXPECT_THAT(r.err, HasSubstr("IMG_02.JPG: not written: Format error in file"));
    EXPECT_THAT(r.out, HasSubstr("wrote 2 of 3 images"));
    EXPECT_NEAR(latitude(name(1)).value_or(0), 10.001, 1e-6);
    EXPECT_NEAR(latitude(name(3)).value_or(0), 10.003, 1e-6);
}

TEST_F(GeotagDir, AFileNameEndingInASpaceIsMatchedAndShownQuoted) {
    captures(2, 2);
    images({{"IMG_01.JPG", kT}, {"IMG_02.JPG ", kT + 2}});
    const auto r = geotag({"--write"});
    EXPECT_EQ(r.status, kExitOk) << r.out << r.err;
    EXPECT_THAT(r.out, HasSubstr("'IMG_02.JPG '  capture 2  +0.00 s"));
    EXPECT_NEAR(latitude("IMG_02.JPG ").value_or(0), 10.002, 1e-6);
}

TEST_F(GeotagDir, MissesAWholeNumberOfHoursOffHintAtTheTimeZone) {
    captures(4, 2);
    images_every(4, 2, 3600);  // a camera set to UTC+1, no OffsetTimeOriginal
    const auto r = geotag({});
    EXPECT_EQ(r.status, kExitFailure);
    EXPECT_THAT(r.err, HasSubstr("4 of the 4 images without a capture are within the tolerance of "
                                 "one 1 h earlier: a camera set to local time? try "
                                 "--clock-offset 3600"));
    const auto given = geotag({"--clock-offset", "0"});
    EXPECT_THAT(given.err, Not(HasSubstr("try --clock-offset"))) << "the user said so";
}

// issue 43: a capture gportd stamped gives its image the stamp's position,
// the camera's direction, the accuracy in Pix4D's XMP and the GPS date and
// time from the autopilot's UTC, which exiftool reads back; one gportd
// marked untagged gets no position, whatever its meta says, and is named.
TEST_F(GeotagDir, TheStampsTagsAreWrittenAndAnUntaggedCaptureGetsNone) {
    {
        std::ofstream file(root_ / "captures.jsonl");
        for (int k = 1; k <= 2; ++k) {
            json c = {{"index", k},
                      {"kind", "photo"},
                      {"utc_us", (kT + (k - 1) * 10) * 1000000 + 900000},  // a companion 0.9 s late
                      {"attitude",
                       {{"imu", {{"pitch", -30.0}, {"roll", 0.0}}},
                        {"hall", {{"pitch", -30.0}, {"roll", 0.0}, {"yaw", -20.0}}}}},
                      {"meta", {{"lat", 1.0}, {"lon", 2.0}}}};
            c["vehicle"] = {{"tagged", k == 1}, {"utc_us", (kT + (k - 1) * 10) * 1000000 + 250000}};
            if (k == 1) {
                c["vehicle"].update({{"lat", 47.397742},
                                     {"lon", 8.545594},
                                     {"alt_msl_m", 488.5},
                                     {"heading_deg", 10.0},
                                     {"h_acc_m", 1.25},
                                     {"v_acc_m", 2.5}});
            } else {
                c["vehicle"]["why"] = "no 3D GPS fix (GPS_FIX_TYPE 1)";
            }
            file << c.dump() << "\n";
        }
    }
    images_every(2, 10, 0);
    const auto ran = geotag({"--clock-offset", "0", "--write"});
    EXPECT_EQ(ran.status, 1) << ran.out << ran.err;
    EXPECT_THAT(ran.err, HasSubstr("IMG_02.JPG"));
    EXPECT_FALSE(latitude("IMG_02.JPG")) << "never the meta's position";

    const auto out = root_ / "stamp.json";
    const auto command =
        "exiftool -json -GPSLatitude# -GPSImgDirection# -GPSImgDirectionRef# "
        "-GPSDateStamp -GPSTimeStamp -XMP:GPSXYAccuracy# -XMP:GPSZAccuracy# '" +
        card() + "/IMG_01.JPG' > '" + out.string() + "' 2>/dev/null";
    ASSERT_EQ(std::system(command.c_str()), 0);
    const auto tags = json::parse(std::ifstream(out))[0];
    EXPECT_EQ(tags["GPSLatitude"], 47.397742);
    EXPECT_EQ(tags["GPSImgDirection"], 350);
    EXPECT_EQ(tags["GPSImgDirectionRef"], "T");
    EXPECT_EQ(tags["GPSDateStamp"], "2026:11:27");
    EXPECT_EQ(tags["GPSTimeStamp"], "07:00:00.25");
    EXPECT_EQ(tags["GPSXYAccuracy"], 1.25);
    EXPECT_EQ(tags["GPSZAccuracy"], 2.5);
}

}  // namespace
}  // namespace gport::cli::geotag_dir_test
