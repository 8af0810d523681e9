// gportctl geotag DIR, the pure part: which image file is which photo
// capture, and what is written into it. Images are matched to captures by
// the camera's clock (EXIF DateTimeOriginal) within a tolerance, one to one,
// closest first; or, when the camera's clock cannot be trusted, in order
// (docs/operations.md, "Photos matched to their files").
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace gport::cli {

// A photo from gportd's capture log, with what is written into its file.
// A photo's capture. Its position is gportd's stamp (`vehicle`, docs/api.md
// "The vehicle") when gportd has a vehicle source, else the meta's; a
// capture gportd marked untagged gets no position, whatever its meta says.
struct PhotoCapture {
    std::uint64_t index = 0;
    std::int64_t utc_us = 0;  // the autopilot's UTC at the shutter when known, else gportd's clock
    std::optional<double> lat, lon, alt_m;   // degrees, metres AMSL
    std::optional<double> pitch, roll;       // the IMU's, degrees (earth-referenced)
    std::optional<double> yaw;               // hall yaw + the vehicle's heading, when both
    std::optional<double> h_acc_m, v_acc_m;  // the stamp's accuracy (1-sigma), when known
    std::optional<std::int64_t> gps_utc_us;  // the autopilot's UTC at the shutter
    std::string untagged;                    // gportd's reason, when it marked it untagged
};

// A capture object as `captures` lists it; empty unless it is a photo.
std::optional<PhotoCapture> photo_capture(const nlohmann::json& capture);

// An image file as exiftool reads it.
struct ImageFile {
    std::string path;                    // exiftool's SourceFile
    std::optional<std::int64_t> utc_us;  // the camera's clock, turned to UTC
    std::string taken;                   // DateTimeOriginal as written, for the report
};

// One entry of `exiftool -json -n -DateTimeOriginal -SubSecTimeOriginal
// -OffsetTimeOriginal`. The camera's local time is turned to UTC with its
// OffsetTimeOriginal when it wrote one, else by `clock_offset_s` (the
// camera's clock minus UTC: 3600 for a camera set to UTC+1).
ImageFile image_file(const nlohmann::json& exif, double clock_offset_s);

struct Match {
    std::size_t image = 0;      // into the images
    std::size_t capture = 0;    // into the captures
    std::int64_t delta_us = 0;  // image time minus capture time (0 in order)
};

struct Matching {
    std::vector<Match> matched;  // in the images' order
    std::vector<std::size_t> images_left, captures_left;
};

// Closest pairs first, each image and capture used once, none further apart
// than `tolerance_us`: a sorted sweep (images and captures merged by time,
// the closest neighbouring pair taken first), O(images + captures) memory.
Matching match_by_time(const std::vector<ImageFile>& images,
                       const std::vector<PhotoCapture>& captures, std::int64_t tolerance_us);

// The images sorted by their time (then name) to the captures by index,
// one by one; what is left over on either side is reported. The caller
// refuses images without a time and unequal counts first (geotag_dir).
Matching match_in_order(const std::vector<ImageFile>& images,
                        const std::vector<PhotoCapture>& captures);

// exiftool's arguments that write `capture` into its file: GPS position
// (EXIF GPSLatitude/Longitude/Altitude with their Refs) and the gimbal's
// angles (XMP drone-dji GimbalPitchDegree/RollDegree/YawDegree, which
// OpenDroneMap and Pix4D read); only what the capture holds.
std::vector<std::string> tag_arguments(const PhotoCapture& capture);

// OpenDroneMap's geo.txt for the matched images with a position: "EPSG:4326",
// then "NAME LON LAT [ALT] YAW PITCH ROLL" (angles 0 when unknown, as ODM
// asks).
std::string geo_txt(const std::vector<ImageFile>& images, const std::vector<PhotoCapture>& captures,
                    const Matching& matching);

}  // namespace gport::cli
