// Running exiftool (Debian's libimage-exiftool-perl) for gportctl geotag:
// reading the images' times, writing the tags. Found on PATH; arguments go
// through an argument file (-@), never a shell, so file names are data.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "gport/base/result.hpp"

namespace gport::cli {

struct ExifError {
    std::string message;
};

// The JPEG files in `dir` (not its subfolders) with DateTimeOriginal,
// SubSecTimeOriginal and OffsetTimeOriginal: exiftool's -json output. An
// error names what failed (exiftool missing: the package to install).
Result<nlohmann::json, ExifError> read_image_times(const std::string& dir);

// Writes each file's tags: one exiftool run for all of them (-execute
// between files). exiftool keeps every original as FILE_original.
// `files[i]` gets `tags[i]`. Empty when done, else the error (with
// exiftool's own message).
std::optional<ExifError> write_image_tags(const std::vector<std::string>& files,
                                          const std::vector<std::vector<std::string>>& tags);

}  // namespace gport::cli
