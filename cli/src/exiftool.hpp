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

// The JPEG files in `dir` (not its subfolders; .jpg or .jpeg in any case,
// trailing blanks after it too) with DateTimeOriginal, SubSecTimeOriginal
// and OffsetTimeOriginal: exiftool's -json output. An error names what
// failed (exiftool missing: the package to install; a file name holding a
// newline, which exiftool's argument file cannot carry: that file).
Result<nlohmann::json, ExifError> read_image_times(const std::string& dir);

// Writes each file's tags: one exiftool run for all of them (-execute
// between files). exiftool keeps every original as FILE_original.
// `files[i]` gets `tags[i]`. One entry a file: empty when written, else
// exiftool's message about it; an error when exiftool could not be run or
// its failure cannot be told apart by file.
Result<std::vector<std::optional<std::string>>, ExifError> write_image_tags(
    const std::vector<std::string>& files, const std::vector<std::vector<std::string>>& tags);

}  // namespace gport::cli
