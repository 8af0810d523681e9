// Issue 32, item 6: photos matched to their files. The real gportd on
// gport-sim logs photos with a position; the test makes JPEG files (a
// minimal valid baseline JPEG, 8x8 grey), gives them the camera's times with
// exiftool, and runs gportctl geotag: the dry run changes nothing, --write
// puts each capture's position and gimbal angles into the right file,
// --geo-txt writes OpenDroneMap's file, --in-order and --captures work, and
// an image with no capture near it is reported.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "minimal_jpeg.hpp"
#include "sim_daemon_fixture.hpp"

namespace gport::testing {
namespace {

namespace fs = std::filesystem;

// Runs a program; its stdout (and, through a shell, stderr) and exit status.
struct Ran {
    int status = -1;
    std::string out;
};
Ran run(std::vector<std::string> argv) {
    std::vector<std::string> sh{"/bin/sh", "-c", "exec \"$0\" \"$@\" 2>&1"};
    sh.insert(sh.end(), argv.begin(), argv.end());
    Process p(sh);
    Ran r;
    while (auto line = p.next_line(60s)) {
        r.out += *line + "\n";
    }
    r.status = p.wait(60s).value_or(-1);
    return r;
}

// EXIF's local time of a UTC instant in µs, as a camera set to UTC+1 writes it.
std::string camera_time(std::int64_t utc_us, std::string* subsec) {
    const std::time_t local = static_cast<std::time_t>(utc_us / 1000000) + 3600;
    std::tm tm{};
    ::gmtime_r(&local, &tm);
    char text[32];
    std::strftime(text, sizeof text, "%Y:%m:%d %H:%M:%S", &tm);
    *subsec = std::to_string((utc_us % 1000000) / 10000 + 100).substr(1);  // two digits
    return text;
}

class Geotag : public SimDaemonTest {
  protected:
    void SetUp() override {
        SimDaemonTest::SetUp();
        ASSERT_EQ(run({"exiftool", "-ver"}).status, 0)
            << "exiftool is missing: apt install libimage-exiftool-perl (scripts/deps.sh)";
        images_ = dir_.file("card");
        fs::create_directory(images_);
    }

    // A photo with `meta`; its capture's utc_us.
    std::int64_t photo(const Json& meta) {
        const auto reply = client_->call("photo", {{"meta", meta}});
        EXPECT_TRUE(reply.contains("result")) << reply.dump();
        const auto index = reply["result"]["capture"]["index"].get<std::uint64_t>();
        const auto list = client_->call("captures", {{"since", index}, {"limit", 1}});
        return list["result"]["captures"][0]["utc_us"].get<std::int64_t>();
    }

    // An image file taken `skew_ms` after `utc_us` by the camera's clock.
    std::string image(const std::string& name, std::int64_t utc_us, std::int64_t skew_ms) {
        const auto path = images_ + "/" + name;
        std::ofstream(path, std::ios::binary) << minimal_jpeg();
        std::string subsec;
        const auto taken = camera_time(utc_us + skew_ms * 1000, &subsec);
        const auto r = run({"exiftool", "-q", "-overwrite_original", "-DateTimeOriginal=" + taken,
                            "-SubSecTimeOriginal=" + subsec, path});
        EXPECT_EQ(r.status, 0) << r.out;
        return path;
    }

    Ran gportctl(std::vector<std::string> args) {
        args.insert(args.begin(), {GPORTCTL_PATH, "--socket", daemon_->socket(), "geotag"});
        return run(args);
    }

    Json tags(const std::string& path) {
        const auto r = run({"exiftool", "-json", "-n", "-GPSLatitude", "-GPSLongitude",
                            "-GPSAltitude", "-XMP-drone-dji:all", path});
        auto j = Json::parse(r.out, nullptr, false);
        return j.is_array() && !j.empty() ? j[0] : Json();
    }

    std::string images_;
};

TEST_F(Geotag, DryRunThenWriteTheRightPositionIntoEachFile) {
    client_->call("angle", {{"pitch", -45}, {"wait", true}}, 15s);
    const auto t1 = photo({{"lat", 47.397742}, {"lon", 8.545594}, {"alt_m", 488.5}});
    std::this_thread::sleep_for(1500ms);
    const auto t2 =
        photo({{"lat", -35.363261}, {"lon", 149.165230}, {"alt_m", 584.1}, {"heading_deg", 90}});
    const auto a = image("DSC_0001.JPG", t1, 300);        // the camera 0.3 s late
    const auto b = image("DSC 0002.jpg", t2, -400);       // a space in the name, 0.4 s early
    const auto stray = image("DSC_0003.JPG", t2, 60000);  // a minute later: no capture
    const auto before = tags(a);

    const auto dry = gportctl({images_, "--clock-offset", "3600"});
    EXPECT_EQ(dry.status, 1) << "one image has no capture:\n" << dry.out;
    // The camera's SubSecTimeOriginal has two digits: the offsets are to 0.01 s.
    EXPECT_NE(dry.out.find("DSC_0001.JPG  capture 1  +0."), std::string::npos) << dry.out;
    EXPECT_NE(dry.out.find(" s  47.3977420 8.5455940 488.5 m pitch "), std::string::npos)
        << dry.out;
    EXPECT_NE(dry.out.find("DSC 0002.jpg  capture 2  -0."), std::string::npos) << dry.out;
    EXPECT_NE(dry.out.find(" s  -35.3632610 149.1652300 584.1 m pitch "), std::string::npos)
        << dry.out;
    EXPECT_NE(dry.out.find("DSC_0003.JPG  no capture within 2.0 s of"), std::string::npos)
        << dry.out;
    EXPECT_NE(dry.out.find("2 of 3 images matched by time; 0 of 2 photo captures without an image"),
              std::string::npos)
        << dry.out;
    EXPECT_NE(dry.out.find("dry run: no image changed"), std::string::npos) << dry.out;
    EXPECT_EQ(tags(a), before) << "the dry run wrote nothing";

    const auto geo = dir_.file("geo.txt");
    const auto wrote = gportctl({images_, "--clock-offset", "3600", "--write", "--geo-txt", geo});
    EXPECT_NE(wrote.out.find("wrote 2 of 2 images (exiftool kept each original as NAME_original)"),
              std::string::npos)
        << wrote.out;
    const auto ta = tags(a);
    EXPECT_NEAR(ta.value("GPSLatitude", 0.0), 47.397742, 1e-6) << ta.dump();
    EXPECT_NEAR(ta.value("GPSLongitude", 0.0), 8.545594, 1e-6) << ta.dump();
    EXPECT_NEAR(ta.value("GPSAltitude", 0.0), 488.5, 1e-3) << ta.dump();
    EXPECT_NEAR(ta.value("GimbalPitchDegree", 0.0), -45.0, 0.6) << ta.dump();
    EXPECT_FALSE(ta.contains("GimbalYawDegree")) << "no heading in its meta";
    const auto tb = tags(b);
    EXPECT_NEAR(tb.value("GPSLatitude", 0.0), -35.363261, 1e-6) << "south: negative" << tb.dump();
    EXPECT_NEAR(tb.value("GPSLongitude", 0.0), 149.16523, 1e-6) << tb.dump();
    EXPECT_NEAR(tb.value("GimbalYawDegree", 0.0), 90.0, 0.6) << "heading 90 + hall yaw 0";
    EXPECT_FALSE(tags(stray).contains("GPSLatitude")) << "the stray image is untouched";
    EXPECT_TRUE(fs::exists(a + "_original")) << "exiftool kept the original";
    std::ifstream geo_file(geo);
    std::stringstream geo_text;
    geo_text << geo_file.rdbuf();
    EXPECT_EQ(geo_text.str().substr(0, 10), "EPSG:4326\n");
    EXPECT_NE(geo_text.str().find("DSC_0001.JPG 8.5455940 47.3977420 488.500 0.00 -45"),
              std::string::npos)
        << geo_text.str();
}

// The attacker: an image whose name holds a newline and an exiftool option
// would add lines to exiftool's argument file. It is refused, naming the
// file, and nothing is written to any image.
TEST_F(Geotag, AFileNameThatWouldInjectAnExiftoolOptionIsRefused) {
    const auto t1 = photo({{"lat", 47.0}, {"lon", 8.0}});
    std::this_thread::sleep_for(1500ms);
    const auto t2 = photo({{"lat", 48.0}, {"lon", 9.0}});
    const auto good = image("GOOD.JPG", t1, 0);
    const auto evil = image("EVIL\n-GPSLatitude=0\n-overwrite_original\n.JPG", t2, 0);
    const auto r = gportctl({images_, "--clock-offset", "3600", "--write"});
    EXPECT_EQ(r.status, 1) << r.out;
    EXPECT_NE(r.out.find("a path holds a line break"), std::string::npos) << r.out;
    EXPECT_FALSE(tags(good).contains("GPSLatitude")) << "nothing written";
    EXPECT_FALSE(tags(evil).contains("GPSLatitude")) << "nothing written";
    EXPECT_FALSE(fs::exists(good + "_original"));
}

// The same through a folder's name: a dry run in a folder whose name holds
// line breaks, `-if` and Perl (beside a folder named as its first line)
// would have exiftool run that Perl while it reads the images' times. It is
// refused before exiftool starts.
TEST_F(Geotag, AFolderNameThatWouldRunPerlInExiftoolIsRefused) {
    const auto t1 = photo({{"lat", 47.0}, {"lon", 8.0}});
    const auto marker = dir_.file("PWNED");
    std::string marker_in_perl = "q{";  // a name holds no '/': chr(47) instead
    for (const char c : marker) {
        marker_in_perl += c == '/' ? std::string("}.chr(47).q{") : std::string(1, c);
    }
    marker_in_perl += "}";
    images_ = dir_.file("x");  // the first line's folder, with an image for -if to test
    fs::create_directory(images_);
    image("A.JPG", t1, 0);
    images_ = dir_.file("x\n-if\nsystem(q{touch }." + marker_in_perl + ") or 1\ny");
    fs::create_directory(images_);
    image("A.JPG", t1, 0);
    const auto r = gportctl({images_, "--clock-offset", "3600"});
    EXPECT_EQ(r.status, 1) << r.out;
    EXPECT_NE(r.out.find("a path holds a line break"), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(marker)) << "exiftool ran the folder name's Perl";
}

// South, west and below sea level (the Dead Sea's shore is 430 m below), into
// an image whose camera already wrote an XMP position in the north: EXIF gets
// S, W and "below sea level", and the XMP position the same signed values.
TEST_F(Geotag, SouthWestAndBelowSeaLevelAgreeInExifAndXmp) {
    const auto t1 = photo({{"lat", -33.4489}, {"lon", -70.6693}, {"alt_m", -12.5}});
    const auto a = image("S.JPG", t1, 0);
    ASSERT_EQ(run({"exiftool", "-q", "-overwrite_original", "-XMP-exif:GPSLatitude=10",
                   "-XMP-exif:GPSLongitude=20", a})
                  .status,
              0);
    const auto r = gportctl({images_, "--clock-offset", "3600", "--write"});
    EXPECT_EQ(r.status, 0) << r.out;
    const auto read = run({"exiftool", "-json", "-n", "-G1", "-a", "-GPS:all", "-XMP-exif:all",
                           "-Composite:GPSAltitude", a});
    auto j = Json::parse(read.out, nullptr, false);
    ASSERT_TRUE(j.is_array() && !j.empty()) << read.out;
    const auto t = j[0];
    EXPECT_EQ(t.value("GPS:GPSLatitudeRef", ""), "S") << t.dump();
    EXPECT_EQ(t.value("GPS:GPSLongitudeRef", ""), "W") << t.dump();
    EXPECT_EQ(t.value("GPS:GPSAltitudeRef", -1), 1) << "below sea level: " << t.dump();
    EXPECT_NEAR(t.value("GPS:GPSAltitude", 0.0), 12.5, 1e-3) << t.dump();
    EXPECT_NEAR(t.value("Composite:GPSAltitude", 0.0), -12.5, 1e-3) << t.dump();
    EXPECT_NEAR(t.value("XMP-exif:GPSLatitude", 0.0), -33.4489, 1e-6) << t.dump();
    EXPECT_NEAR(t.value("XMP-exif:GPSLongitude", 0.0), -70.6693, 1e-6) << t.dump();
}

TEST_F(Geotag, InOrderAndFromCaptureLogFiles) {
    const auto t1 = photo({{"lat", 10.0}, {"lon", 20.0}});
    const auto t2 = photo({{"lat", 11.0}, {"lon", 21.0}});
    // A camera whose clock was never set: an hour and a day off.
    image("P1.JPG", t1, 90000000);
    image("P2.JPG", t2, 90000000);
    const auto by_time = gportctl({images_});
    EXPECT_EQ(by_time.status, 1);
    EXPECT_NE(by_time.out.find("0 of 2 images matched by time"), std::string::npos) << by_time.out;
    const auto in_order = gportctl({images_, "--in-order"});
    EXPECT_EQ(in_order.status, 0) << in_order.out;
    EXPECT_NE(in_order.out.find("P1.JPG  capture 1  10.0000000 20.0000000"), std::string::npos)
        << in_order.out;
    EXPECT_NE(in_order.out.find("P2.JPG  capture 2  11.0000000 21.0000000"), std::string::npos)
        << in_order.out;
    // The same from a copy of the capture log, with no daemon asked.
    const auto log = dir_.file("captures.jsonl");
    {
        std::ofstream file(log);
        const auto listed = client_->call("captures", Json::object());
        ASSERT_TRUE(listed["result"]["captures"].is_array()) << listed.dump();
        for (const auto& c : listed["result"]["captures"]) {
            file << c.dump() << "\n";
        }
        file << "not json\n";  // a torn line is skipped
    }
    const auto from_file = run({GPORTCTL_PATH, "--socket", "/nonexistent.sock", "geotag", images_,
                                "--in-order", "--captures", log});
    EXPECT_EQ(from_file.status, 0) << from_file.out;
    EXPECT_NE(from_file.out.find("P2.JPG  capture 2"), std::string::npos) << from_file.out;
    const auto missing = run({GPORTCTL_PATH, "geotag", images_, "--captures", dir_.file("none")});
    EXPECT_EQ(missing.status, 66) << missing.out;
    EXPECT_NE(missing.out.find("cannot read"), std::string::npos) << missing.out;
}

}  // namespace
}  // namespace gport::testing
