#include "image_tags.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <tuple>
#include <utility>

#include "gport/base/civil_time.hpp"
#include "gport/client/capture_files.hpp"

namespace gport::cli {
namespace {

using nlohmann::json;

std::optional<double> number_at(const json& object, const char* key) {
    if (!object.is_object()) {
        return std::nullopt;
    }
    const auto it = object.find(key);
    if (it == object.end() || !it->is_number()) {
        return std::nullopt;
    }
    return it->get<double>();
}

// "2026:11:27 14:03:05" (EXIF's local time) -> seconds since the epoch as
// if it were UTC; empty when it is not that shape.
std::optional<std::int64_t> exif_seconds(const std::string& text) {
    int year = 0;
    unsigned month = 0;
    unsigned day = 0;
    unsigned hour = 0;
    unsigned minute = 0;
    unsigned second = 0;
    char tail = 0;
    if (std::sscanf(text.c_str(), "%4d:%2u:%2u %2u:%2u:%2u%c", &year, &month, &day, &hour, &minute,
                    &second, &tail) != 6 ||
        year < 1970 || hour > 23 || minute > 59 || second > 60) {
        return std::nullopt;
    }
    return base::epoch_seconds(year, month, day, hour, minute, second);
}

// "+01:00" / "-05:30" -> seconds east of UTC.
std::optional<std::int64_t> offset_seconds(const json& value) {
    if (!value.is_string()) {
        return std::nullopt;
    }
    const auto text = value.get<std::string>();
    int hours = 0;
    int minutes = 0;
    char sign = 0;
    if (std::sscanf(text.c_str(), "%c%2d:%2d", &sign, &hours, &minutes) != 3 ||
        (sign != '+' && sign != '-') || hours > 14 || minutes > 59) {
        return std::nullopt;
    }
    const std::int64_t s = hours * 3600 + minutes * 60;
    return sign == '-' ? -s : s;
}

// SubSecTimeOriginal: the digits of a fraction of a second ("25" = 0.25 s);
// exiftool -n may give it as a number.
std::int64_t subsecond_us(const json& value) {
    std::string digits = value.is_string()           ? value.get<std::string>()
                         : value.is_number_integer() ? std::to_string(value.get<std::int64_t>())
                                                     : std::string();
    if (digits.empty() || digits.size() > 9 ||
        !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; })) {
        return 0;
    }
    digits.resize(6, '0');
    return std::stoll(digits);
}

std::string name_of(const std::string& path) {
    return std::filesystem::path(path).filename().string();
}

// exiftool's GPSDateStamp and GPSTimeStamp values for a UTC; none past the
// four digits EXIF's date has for the year (a captures file may hold any).
std::optional<std::pair<std::string, std::string>> gps_date_time(std::int64_t utc_us) {
    const auto t = base::civil_time(utc_us);
    if (t.year < 1 || t.year > 9999) {
        return std::nullopt;
    }
    return std::pair{fmt::format("{:04}:{:02}:{:02}", t.year, t.month, t.day),
                     fmt::format("{:02}:{:02}:{:02}.{:06}", t.hour, t.minute, t.second, t.micros)};
}

}  // namespace

std::optional<PhotoCapture> photo_capture(const json& capture) {
    if (!capture.is_object() || capture.value("kind", "") != "photo") {
        return std::nullopt;
    }
    const auto index = capture.find("index");
    const auto utc = capture.find("utc_us");
    if (index == capture.end() || !index->is_number_unsigned() || utc == capture.end() ||
        !utc->is_number_integer()) {
        return std::nullopt;
    }
    PhotoCapture p;
    p.index = index->get<std::uint64_t>();
    p.utc_us = utc->get<std::int64_t>();
    // One rule with the CSV and GeoJSON: gportd's stamp, none when it marked
    // the capture untagged, the meta's when it had no vehicle.
    const auto where =
        client::capture_position(capture.dump(-1, ' ', false, json::error_handler_t::replace));
    p.lat = where.lat;
    p.lon = where.lon;
    p.alt_m = where.alt_m;
    p.h_acc_m = where.h_acc_m;
    p.v_acc_m = where.v_acc_m;
    p.gps_utc_us = where.gps_utc_us;
    p.untagged = where.untagged;
    if (p.gps_utc_us) {
        p.utc_us = *p.gps_utc_us;  // true time: the images are matched by it
    }
    const auto heading = where.heading_deg;
    const json attitude = capture.value("attitude", json());
    const json imu = attitude.is_object() ? attitude.value("imu", json()) : json();
    const json hall = attitude.is_object() ? attitude.value("hall", json()) : json();
    p.pitch = number_at(imu, "pitch");
    p.roll = number_at(imu, "roll");
    const auto hall_yaw = number_at(hall, "yaw");
    if (heading && hall_yaw) {
        p.yaw = std::remainder(*heading + *hall_yaw, 360.0);
    }
    return p;
}

ImageFile image_file(const json& exif, double clock_offset_s) {
    ImageFile f;
    f.path = exif.value("SourceFile", "");
    const json taken = exif.value("DateTimeOriginal", json());
    f.taken = taken.is_string() ? taken.get<std::string>() : std::string();
    if (const auto local = exif_seconds(f.taken)) {
        const auto offset = offset_seconds(exif.value("OffsetTimeOriginal", json()));
        const auto shift_us = offset
                                  ? *offset * 1000000
                                  : static_cast<std::int64_t>(std::llround(clock_offset_s * 1e6));
        f.utc_us =
            *local * 1000000 + subsecond_us(exif.value("SubSecTimeOriginal", json())) - shift_us;
    }
    return f;
}

namespace {

// match_by_time's sweep: images and captures in one list sorted by time,
// linked so that a matched pair leaves its neighbours adjacent; the closest
// image-capture pair still unmatched is always a neighbouring one.
class Sweep {
  public:
    Sweep(const std::vector<ImageFile>& images, const std::vector<PhotoCapture>& captures,
          std::int64_t tolerance_us)
        : tolerance_us_(tolerance_us) {
        for (std::size_t i = 0; i < images.size(); ++i) {
            if (images[i].utc_us) {
                points_.push_back({*images[i].utc_us, true, i});
            }
        }
        for (std::size_t c = 0; c < captures.size(); ++c) {
            points_.push_back({captures[c].utc_us, false, c});
        }
        std::sort(points_.begin(), points_.end(), [](const Point& a, const Point& b) {
            return std::tie(a.t, a.image, a.index) < std::tie(b.t, b.image, b.index);
        });
        const auto n = points_.size();
        prev_.resize(n);
        next_.resize(n);
        alive_.assign(n, true);
        for (std::size_t k = 0; k < n; ++k) {
            prev_[k] = k == 0 ? kNone : k - 1;
            next_[k] = k + 1 < n ? k + 1 : kNone;
            consider(k, next_[k]);
        }
    }

    // The pairs, closest first (ties: lower image, then capture, first).
    std::vector<Match> run() {
        std::vector<Match> matched;
        while (!heap_.empty()) {
            std::pop_heap(heap_.begin(), heap_.end(), std::greater<>());
            const auto [delta, image, capture, left, right] = heap_.back();
            heap_.pop_back();
            if (!alive_[left] || !alive_[right]) {
                continue;
            }
            const auto& l = points_[left];
            const auto& r = points_[right];
            matched.push_back({image, capture, l.image ? l.t - r.t : r.t - l.t});
            alive_[left] = alive_[right] = false;
            const auto before = prev_[left];
            const auto after = next_[right];
            link(before, after);
            consider(before, after);
        }
        return matched;
    }

  private:
    static constexpr std::size_t kNone = static_cast<std::size_t>(-1);
    struct Point {
        std::int64_t t;
        bool image;
        std::size_t index;
    };
    // |delta|, image, capture, the two points
    using Pair = std::tuple<std::int64_t, std::size_t, std::size_t, std::size_t, std::size_t>;

    void link(std::size_t before, std::size_t after) {
        if (before != kNone) {
            next_[before] = after;
        }
        if (after != kNone) {
            prev_[after] = before;
        }
    }

    void consider(std::size_t left, std::size_t right) {
        if (left == kNone || right == kNone || points_[left].image == points_[right].image) {
            return;
        }
        const auto delta = points_[right].t - points_[left].t;
        if (delta > tolerance_us_) {
            return;
        }
        const auto& img = points_[left].image ? points_[left] : points_[right];
        const auto& cap = points_[left].image ? points_[right] : points_[left];
        heap_.emplace_back(delta, img.index, cap.index, left, right);
        std::push_heap(heap_.begin(), heap_.end(), std::greater<>());
    }

    std::int64_t tolerance_us_;
    std::vector<Point> points_;
    std::vector<std::size_t> prev_, next_;
    std::vector<bool> alive_;
    std::vector<Pair> heap_;
};

std::vector<std::size_t> unused(std::size_t n, const std::vector<bool>& used) {
    std::vector<std::size_t> out;
    for (std::size_t k = 0; k < n; ++k) {
        if (!used[k]) {
            out.push_back(k);
        }
    }
    return out;
}

}  // namespace

Matching match_by_time(const std::vector<ImageFile>& images,
                       const std::vector<PhotoCapture>& captures, std::int64_t tolerance_us) {
    Matching m;
    m.matched = Sweep(images, captures, tolerance_us).run();
    std::sort(m.matched.begin(), m.matched.end(),
              [](const Match& a, const Match& b) { return a.image < b.image; });
    std::vector<bool> image_used(images.size()), capture_used(captures.size());
    for (const auto& match : m.matched) {
        image_used[match.image] = capture_used[match.capture] = true;
    }
    m.images_left = unused(images.size(), image_used);
    m.captures_left = unused(captures.size(), capture_used);
    return m;
}

Matching match_in_order(const std::vector<ImageFile>& images,
                        const std::vector<PhotoCapture>& captures) {
    std::vector<std::size_t> by_time(images.size()), by_index(captures.size());
    for (std::size_t i = 0; i < by_time.size(); ++i) {
        by_time[i] = i;
    }
    for (std::size_t c = 0; c < by_index.size(); ++c) {
        by_index[c] = c;
    }
    std::stable_sort(by_time.begin(), by_time.end(), [&](std::size_t a, std::size_t b) {
        return std::tuple(images[a].utc_us.value_or(0), name_of(images[a].path)) <
               std::tuple(images[b].utc_us.value_or(0), name_of(images[b].path));
    });
    std::stable_sort(by_index.begin(), by_index.end(), [&](std::size_t a, std::size_t b) {
        return captures[a].index < captures[b].index;
    });
    Matching m;
    const std::size_t n = std::min(by_time.size(), by_index.size());
    for (std::size_t k = 0; k < n; ++k) {
        m.matched.push_back({by_time[k], by_index[k], 0});
    }
    m.images_left.assign(by_time.begin() + static_cast<std::ptrdiff_t>(n), by_time.end());
    m.captures_left.assign(by_index.begin() + static_cast<std::ptrdiff_t>(n), by_index.end());
    return m;
}

std::vector<std::string> tag_arguments(const PhotoCapture& c) {
    std::vector<std::string> args;
    // Signed values, each reference from the same number: exiftool stores
    // EXIF's magnitude and S, W or below sea level from the sign, and a
    // signed XMP-exif GPS tag already in the image gets the same value. (An
    // unsigned value with "-GPSLatitudeRef=S" left an existing XMP latitude
    // north, and "-GPSAltitudeRef=1" was read as "above sea level".)
    if (c.lat && c.lon) {
        args.push_back(fmt::format("-GPSLatitude={:.7f}", *c.lat));
        args.push_back(fmt::format("-GPSLatitudeRef={:.7f}", *c.lat));
        args.push_back(fmt::format("-GPSLongitude={:.7f}", *c.lon));
        args.push_back(fmt::format("-GPSLongitudeRef={:.7f}", *c.lon));
        if (c.alt_m) {
            args.push_back(fmt::format("-GPSAltitude={:.3f}", *c.alt_m));
            args.push_back(fmt::format("-GPSAltitudeRef={:.3f}", *c.alt_m));
        }
    }
    if (c.pitch) {
        args.push_back(fmt::format("-XMP-drone-dji:GimbalPitchDegree={:.2f}", *c.pitch));
    }
    if (c.roll) {
        args.push_back(fmt::format("-XMP-drone-dji:GimbalRollDegree={:.2f}", *c.roll));
    }
    if (c.yaw) {
        args.push_back(fmt::format("-XMP-drone-dji:GimbalYawDegree={:.2f}", *c.yaw));
        // The camera's direction, true north (0 to 360).
        args.push_back(fmt::format("-GPSImgDirection={:.2f}", std::fmod(*c.yaw + 360.0, 360.0)));
        args.push_back("-GPSImgDirectionRef=T");
    }
    if (c.lat && c.lon && c.h_acc_m) {  // Pix4D's XMP, 1-sigma metres (ODM reads it too)
        args.push_back(fmt::format("-XMP-Camera:GPSXYAccuracy={:.3f}", *c.h_acc_m));
    }
    if (c.lat && c.lon && c.v_acc_m) {
        args.push_back(fmt::format("-XMP-Camera:GPSZAccuracy={:.3f}", *c.v_acc_m));
    }
    if (const auto stamp =
            c.lat && c.lon && c.gps_utc_us ? gps_date_time(*c.gps_utc_us) : std::nullopt) {
        args.push_back("-GPSDateStamp=" + stamp->first);
        args.push_back("-GPSTimeStamp=" + stamp->second);
    }
    return args;
}

std::string geo_txt(const std::vector<ImageFile>& images, const std::vector<PhotoCapture>& captures,
                    const Matching& matching) {
    std::string out = "EPSG:4326\n";
    for (const auto& m : matching.matched) {
        const auto& c = captures[m.capture];
        if (!c.lat || !c.lon) {
            continue;
        }
        out += fmt::format("{} {:.7f} {:.7f}", name_of(images[m.image].path), *c.lon, *c.lat);
        if (c.alt_m) {
            out += fmt::format(" {:.3f} {:.2f} {:.2f} {:.2f}", *c.alt_m, c.yaw.value_or(0.0),
                               c.pitch.value_or(0.0), c.roll.value_or(0.0));
            // OpenDroneMap reads the accuracy only with all nine columns.
            if (c.h_acc_m && c.v_acc_m) {
                out += fmt::format(" {:.3f} {:.3f}", *c.h_acc_m, *c.v_acc_m);
            }
        }
        out += "\n";
    }
    return out;
}

}  // namespace gport::cli
