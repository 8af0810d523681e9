#include "geotag_dir.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>

#include "clock_offset.hpp"
#include "exiftool.hpp"
#include "gport/cli/captures.hpp"
#include "gport/cli/printable.hpp"
#include "gport/client/capture_files.hpp"
#include "gport/contract/names.hpp"
#include "image_tags.hpp"

namespace gport::cli {
namespace {

using nlohmann::json;

constexpr long kPage = 1000;

// A file's name as printed: quoted when it starts or ends with a blank,
// which would be invisible.
std::string shown_name(const std::string& path) {
    const auto name = std::filesystem::path(path).filename().string();
    const bool blank_edge = name.empty() ||
                            std::isspace(static_cast<unsigned char>(name.front())) ||
                            std::isspace(static_cast<unsigned char>(name.back()));
    return blank_edge ? fmt::format("'{}'", printable(name)) : printable(name);
}

// Up to ten of the images' names, then how many more.
std::string names(const std::vector<ImageFile>& images, const std::vector<std::size_t>& which) {
    std::string out;
    for (std::size_t k = 0; k < which.size() && k < 10; ++k) {
        out += (k > 0 ? ", " : "") + shown_name(images[which[k]].path);
    }
    return which.size() > 10 ? fmt::format("{} and {} more", out, which.size() - 10) : out;
}

// The photos at or after `since` from gportd, page by page.
int captures_from_gportd(const Invocation& inv, const CallFn& call,
                         std::vector<PhotoCapture>& photos) {
    std::uint64_t since = inv.since;
    for (bool more = true; more;) {
        json result;
        if (const int s =
                call(contract::method::kCaptures, {{"since", since}, {"limit", kPage}}, result);
            s != kExitOk) {
            return s;
        }
        const auto page = read_captures_page(result, since);
        for (const auto& capture : page.captures) {
            if (auto p = photo_capture(capture)) {
                photos.push_back(*p);
            }
        }
        since = page.next;
        more = page.more;
    }
    return kExitOk;
}

// The photos at or after `since` from capture log files (captures.jsonl and
// its rotated copies); an unreadable file is an error, a bad line is skipped.
int captures_from_files(const Invocation& inv, std::vector<PhotoCapture>& photos,
                        std::ostream& err) {
    for (const auto& path : inv.captures_files) {
        std::ifstream file(path);
        if (!file) {
            err << fmt::format("gportctl: geotag: cannot read {}\n", printable(path));
            return gport::kExitNoInput;
        }
        for (std::string line; std::getline(file, line);) {
            if (auto p = photo_capture(json::parse(line, nullptr, false));
                p && p->index >= inv.since) {
                photos.push_back(*p);
            }
        }
    }
    return kExitOk;
}

std::string seconds(std::int64_t us) {
    return fmt::format("{:+.2f} s", static_cast<double>(us) / 1e6);
}

std::string position(const PhotoCapture& c) {
    if (!c.lat || !c.lon) {
        return c.untagged.empty() ? "no position in its meta" : "untagged by gportd: " + c.untagged;
    }
    return fmt::format("{:.7f} {:.7f}{}", *c.lat, *c.lon,
                       c.alt_m ? fmt::format(" {:.1f} m", *c.alt_m) : std::string());
}

std::string angles(const PhotoCapture& c) {
    std::string out;
    if (c.pitch) {
        out += fmt::format(" pitch {:.2f}", *c.pitch);
    }
    if (c.roll) {
        out += fmt::format(" roll {:.2f}", *c.roll);
    }
    if (c.yaw) {
        out += fmt::format(" yaw {:.2f}", *c.yaw);
    }
    return out;
}

void report(const Invocation& inv, const std::vector<ImageFile>& images,
            const std::vector<PhotoCapture>& photos, const Matching& m, std::ostream& out) {
    for (const auto& match : m.matched) {
        const auto& c = photos[match.capture];
        out << fmt::format("{}  capture {}{}  {}{}\n", shown_name(images[match.image].path),
                           c.index, inv.in_order ? std::string() : "  " + seconds(match.delta_us),
                           position(c), angles(c));
    }
    for (const auto i : m.images_left) {
        out << fmt::format(
            "{}  no capture{}\n", shown_name(images[i].path),
            inv.in_order ? std::string(" left (more images than photos)")
            : images[i].utc_us
                ? fmt::format(" within {:.1f} s of {} (camera time)",
                              inv.tolerance.count() / 1000.0, printable(images[i].taken))
                : std::string(" to match: no DateTimeOriginal to match it by"));
    }
    for (const auto c : m.captures_left) {
        out << fmt::format("capture {} ({})  no image\n", photos[c].index,
                           client::utc_text(photos[c].utc_us));
    }
    out << fmt::format("{} of {} images matched{}; {} of {} photo captures without an image\n",
                       m.matched.size(), images.size(), inv.in_order ? " in order" : " by time",
                       m.captures_left.size(), photos.size());
}

// Writes the matched captures' tags; false when a file was not written
// (each named with exiftool's message).
bool write_tags(const std::vector<ImageFile>& images, const std::vector<PhotoCapture>& photos,
                const Matching& m, std::ostream& out, std::ostream& err) {
    std::vector<std::string> files;
    std::vector<std::vector<std::string>> tags;
    for (const auto& match : m.matched) {
        auto args = tag_arguments(photos[match.capture]);
        if (!args.empty()) {
            files.push_back(images[match.image].path);
            tags.push_back(std::move(args));
        }
    }
    if (files.empty()) {
        out << "nothing to write: no image matched a capture with a position or angles\n";
        return true;
    }
    auto result = write_image_tags(files, tags);
    if (!result) {
        err << "gportctl: geotag: " << printable(result.error().message) << "\n";
        return false;
    }
    std::size_t written = 0;
    for (std::size_t i = 0; i < files.size(); ++i) {
        if (const auto& error = (*result)[i]) {
            err << fmt::format("gportctl: geotag: {}: not written: {}\n", shown_name(files[i]),
                               printable(*error));
        } else {
            ++written;
        }
    }
    out << fmt::format("wrote {} of {} image{} (exiftool kept each original as NAME_original)\n",
                       written, files.size(), files.size() == 1 ? "" : "s");
    return written == files.size();
}

// --in-order needs every image's time and as many images as captures.
bool in_order_possible(const std::vector<ImageFile>& images,
                       const std::vector<PhotoCapture>& photos, std::ostream& err) {
    std::vector<std::size_t> untimed;
    for (std::size_t i = 0; i < images.size(); ++i) {
        if (!images[i].utc_us) {
            untimed.push_back(i);
        }
    }
    if (!untimed.empty()) {
        err << fmt::format(
            "gportctl: geotag: --in-order orders the images by their DateTimeOriginal, and {} "
            "of {} have none: {}\n",
            untimed.size(), images.size(), names(images, untimed));
        return false;
    }
    if (images.size() != photos.size()) {
        err << fmt::format(
            "gportctl: geotag: --in-order needs as many images as photo captures: {} images, {} "
            "captures; a shot the camera missed (or took unasked) would shift every image after "
            "it to the wrong capture. Remove what does not belong (--since, --captures, the "
            "files) or match by time\n",
            images.size(), photos.size());
        return false;
    }
    return true;
}

// The camera clock offset the images pair best at must be the one given
// (within kMarginUs) and the only one that pairs as many, unless --force.
constexpr std::int64_t kWindowUs = 500000;
constexpr std::int64_t kMarginUs = 1000000;

std::string clock_text(double given_s, std::int64_t offset_us) {
    return fmt::format("{:+.1f} s", given_s + static_cast<double>(offset_us) / 1e6);
}

// Why the estimate contradicts --clock-offset; empty when it does not.
std::string offset_problem(const OffsetEstimate& e, double given, std::size_t images) {
    if (e.rival_us) {
        return fmt::format(
            "the images pair as well with the camera's clock at {} as at {} ({} of {} images): "
            "ambiguous; check the camera's clock, match --in-order, or pass the right "
            "--clock-offset with --force",
            clock_text(given, e.offset_us), clock_text(given, *e.rival_us), e.pairs, images);
    }
    if (std::llabs(e.offset_us) <= kMarginUs) {
        return {};
    }
    return fmt::format(
        "the images pair best with the captures when the camera's clock is {} off UTC ({} of {} "
        "images, against {} at --clock-offset {}): pass --clock-offset {:.1f} to use it, or "
        "--force to match at {} anyway",
        clock_text(given, e.offset_us), e.pairs, images, e.pairs_at_given, clock_text(given, 0),
        given + static_cast<double>(e.offset_us) / 1e6, clock_text(given, 0));
}

bool offset_accepted(const Invocation& inv, const std::vector<ImageFile>& images,
                     const std::vector<PhotoCapture>& photos, std::ostream& out,
                     std::ostream& err) {
    const auto tolerance_us = static_cast<std::int64_t>(inv.tolerance.count()) * 1000;
    const auto window_us = std::min(tolerance_us, kWindowUs);
    const auto e = estimate_offset(images, photos, tolerance_us, window_us);
    if (e.pairs == 0) {
        return true;
    }
    const auto given = inv.clock_offset_s;
    out << fmt::format(
        "camera clock: UTC{} by the images ({} of {} within {:.1f} s of a capture); "
        "--clock-offset {} pairs {}\n",
        clock_text(given, e.offset_us), e.pairs, images.size(), window_us / 1e6,
        clock_text(given, 0), e.pairs_at_given);
    const auto problem = offset_problem(e, given, images.size());
    if (problem.empty()) {
        return true;
    }
    err << "gportctl: geotag: " << (inv.force ? "--force: " : "") << problem << "\n";
    return inv.force;
}

// Images whose capture holds no position: they get none.
std::vector<std::size_t> without_position(const std::vector<PhotoCapture>& photos,
                                          const Matching& m) {
    std::vector<std::size_t> out;
    for (const auto& match : m.matched) {
        if (!photos[match.capture].lat || !photos[match.capture].lon) {
            out.push_back(match.image);
        }
    }
    return out;
}

// Without --clock-offset: the whole hours that would pair at least half of
// the unmatched images, if any.
void hint_time_zone(const Invocation& inv, const std::vector<ImageFile>& images,
                    const std::vector<PhotoCapture>& photos, const Matching& m, std::ostream& err) {
    if (inv.in_order || inv.clock_offset_given) {
        return;
    }
    const auto shift = hour_shift(images, m.images_left, photos,
                                  static_cast<std::int64_t>(inv.tolerance.count()) * 1000);
    if (!shift || shift->images * 2 < m.images_left.size()) {
        return;
    }
    err << fmt::format(
        "gportctl: geotag: {} of the {} images without a capture are within the tolerance of "
        "one {} h {}: a camera set to local time? try --clock-offset {}\n",
        shift->images, m.images_left.size(), std::abs(shift->hours),
        shift->hours > 0 ? "earlier" : "later", shift->hours * 3600);
}

// What stays unmatched or without a position, said on stderr; false then.
bool all_placed(const Invocation& inv, const std::vector<ImageFile>& images,
                const std::vector<PhotoCapture>& photos, const Matching& m, std::ostream& err) {
    hint_time_zone(inv, images, photos, m, err);
    const auto unplaced = without_position(photos, m);
    if (!unplaced.empty()) {
        err << fmt::format(
            "gportctl: geotag: {} image{} matched a capture with no position (none in its meta, "
            "or gportd marked it untagged: no fit position at the shutter) and get none: {}\n",
            unplaced.size(), unplaced.size() == 1 ? "" : "s", names(images, unplaced));
    }
    return m.images_left.empty() && unplaced.empty() && !images.empty();
}

bool write_geo_txt(const Invocation& inv, const std::vector<ImageFile>& images,
                   const std::vector<PhotoCapture>& photos, const Matching& m, std::ostream& out,
                   std::ostream& err) {
    std::ofstream file(inv.geo_txt, std::ios::trunc);
    if (!(file << geo_txt(images, photos, m)).flush()) {
        err << fmt::format("gportctl: geotag: cannot write {}\n", printable(inv.geo_txt));
        return false;
    }
    out << fmt::format("wrote {} (OpenDroneMap's image geolocation file)\n",
                       printable(inv.geo_txt));
    return true;
}

// The images as exiftool read them, sorted by path; an error said.
int read_images(const Invocation& inv, std::vector<ImageFile>& images, std::ostream& err) {
    const auto dir = std::filesystem::absolute(inv.geotag_dir).string();  // never "-..."
    auto exif = read_image_times(dir);
    if (!exif) {
        err << "gportctl: geotag: " << printable(exif.error().message) << "\n";
        return exif.error().message.find("apt install") != std::string::npos ? kExitUnavailable
                                                                             : kExitError;
    }
    for (const auto& entry : *exif) {
        images.push_back(image_file(entry, inv.clock_offset_s));
    }
    std::sort(images.begin(), images.end(),
              [](const ImageFile& a, const ImageFile& b) { return a.path < b.path; });
    return kExitOk;
}

}  // namespace

int geotag_dir(const Invocation& inv, const CallFn& call, std::ostream& out, std::ostream& err) {
    std::vector<ImageFile> images;
    if (const int read = read_images(inv, images, err); read != kExitOk) {
        return read;
    }
    std::vector<PhotoCapture> photos;
    const int got = inv.captures_files.empty() ? captures_from_gportd(inv, call, photos)
                                               : captures_from_files(inv, photos, err);
    if (got != kExitOk) {
        return got;
    }
    if (inv.in_order ? !in_order_possible(images, photos, err)
                     : !offset_accepted(inv, images, photos, out, err)) {
        return kExitError;
    }
    const auto matching = inv.in_order
                              ? match_in_order(images, photos)
                              : match_by_time(images, photos, inv.tolerance.count() * 1000);
    report(inv, images, photos, matching, out);
    bool ok = all_placed(inv, images, photos, matching, err);
    if (!inv.geo_txt.empty() && !write_geo_txt(inv, images, photos, matching, out, err)) {
        return kExitError;
    }
    if (inv.write) {
        ok = write_tags(images, photos, matching, out, err) && ok;
    } else if (!matching.matched.empty()) {
        out << "dry run: no image changed; --write writes the positions and angles above\n";
    }
    return ok ? kExitOk : kExitError;
}

}  // namespace gport::cli
