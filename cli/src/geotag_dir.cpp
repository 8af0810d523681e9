#include "geotag_dir.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

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

std::string shown_name(const std::string& path) {
    return printable(std::filesystem::path(path).filename().string());
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
        return "no position in its meta";
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
                : std::string(" time: no DateTimeOriginal (try --in-order)"));
    }
    for (const auto c : m.captures_left) {
        out << fmt::format("capture {} ({})  no image\n", photos[c].index,
                           client::utc_text(photos[c].utc_us));
    }
    out << fmt::format("{} of {} images matched{}; {} of {} photo captures without an image\n",
                       m.matched.size(), images.size(), inv.in_order ? " in order" : " by time",
                       m.captures_left.size(), photos.size());
}

int write_tags(const std::vector<ImageFile>& images, const std::vector<PhotoCapture>& photos,
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
        return kExitOk;
    }
    if (auto failed = write_image_tags(files, tags)) {
        err << "gportctl: geotag: " << printable(failed->message) << "\n";
        return kExitError;
    }
    out << fmt::format("wrote {} image{} (exiftool kept each original as NAME_original)\n",
                       files.size(), files.size() == 1 ? "" : "s");
    return kExitOk;
}

}  // namespace

int geotag_dir(const Invocation& inv, const CallFn& call, std::ostream& out, std::ostream& err) {
    const auto dir = std::filesystem::absolute(inv.geotag_dir).string();  // never "-..."
    auto exif = read_image_times(dir);
    if (!exif) {
        err << "gportctl: geotag: " << printable(exif.error().message) << "\n";
        return exif.error().message.find("apt install") != std::string::npos ? kExitUnavailable
                                                                             : kExitError;
    }
    std::vector<ImageFile> images;
    for (const auto& entry : *exif) {
        images.push_back(image_file(entry, inv.clock_offset_s));
    }
    std::sort(images.begin(), images.end(),
              [](const ImageFile& a, const ImageFile& b) { return a.path < b.path; });
    std::vector<PhotoCapture> photos;
    const int got = inv.captures_files.empty() ? captures_from_gportd(inv, call, photos)
                                               : captures_from_files(inv, photos, err);
    if (got != kExitOk) {
        return got;
    }
    const auto matching = inv.in_order
                              ? match_in_order(images, photos)
                              : match_by_time(images, photos, inv.tolerance.count() * 1000);
    report(inv, images, photos, matching, out);
    if (!inv.geo_txt.empty()) {
        std::ofstream file(inv.geo_txt, std::ios::trunc);
        if (!(file << geo_txt(images, photos, matching)).flush()) {
            err << fmt::format("gportctl: geotag: cannot write {}\n", printable(inv.geo_txt));
            return kExitError;
        }
        out << fmt::format("wrote {} (OpenDroneMap's image geolocation file)\n",
                           printable(inv.geo_txt));
    }
    int status = kExitOk;
    if (inv.write) {
        status = write_tags(images, photos, matching, out, err);
    } else if (!matching.matched.empty()) {
        out << "dry run: no image changed; --write writes the positions and angles above\n";
    }
    return status != kExitOk || !matching.images_left.empty() || images.empty() ? kExitError
                                                                                : kExitOk;
}

}  // namespace gport::cli
