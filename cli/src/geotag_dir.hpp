// gportctl geotag DIR: matches the camera's image files in DIR to gportd's
// photo captures and writes each capture's position and gimbal angles into
// its file with exiftool; a dry run unless --write (docs/operations.md,
// "Photos matched to their files").
#pragma once

#include <ostream>

#include "gport/cli/options.hpp"
#include "wait.hpp"

namespace gport::cli {

// 0 when every image matched a capture with a position (and, with --write,
// was written); 1 when one did not (named), when matching is refused (by
// time: the camera's clock the data shows is not --clock-offset, or two
// offsets pair as well, unless --force; --in-order: an image without a time,
// or as many images as captures not), or exiftool failed; 69 when gportd
// cannot be asked for the captures, 66 when a --captures file cannot be read.
int geotag_dir(const Invocation& inv, const CallFn& call, std::ostream& out, std::ostream& err);

}  // namespace gport::cli
