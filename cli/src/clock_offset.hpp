// gportctl geotag DIR: the camera's clock as the data tells it, before
// matching by time (docs/operations.md, "Photos matched to their files"):
// the offset that pairs the most images with captures, a rival that pairs as
// many (ambiguous), and the whole hours that would bring misses in (a camera
// set to local time).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "image_tags.hpp"

namespace gport::cli {

// The camera's clock as the data tells it: the offset (image time minus
// capture time, on top of the offset the images' times already have) that
// pairs the most images with captures within `window_us`, one to one,
// searched within +-`search_us`; offset 0 (the one given) wins a tie.
struct OffsetEstimate {
    std::int64_t offset_us = 0;
    std::size_t pairs = 0;           // images paired at offset_us (0: nothing pairs)
    std::size_t pairs_at_given = 0;  // images paired at offset 0
    // Another offset, more than two windows away, that pairs as many images:
    // the pairing is ambiguous.
    std::optional<std::int64_t> rival_us;
};
OffsetEstimate estimate_offset(const std::vector<ImageFile>& images,
                               const std::vector<PhotoCapture>& captures, std::int64_t search_us,
                               std::int64_t window_us);

// The whole number of hours (-14..14, not 0) that, added to the camera's
// clock offset, brings the most of the images `left` within `tolerance_us`
// of a capture, and how many; empty when no such shift brings any (a camera
// set to local time, its images without OffsetTimeOriginal).
struct HourShift {
    int hours = 0;
    std::size_t images = 0;
};
std::optional<HourShift> hour_shift(const std::vector<ImageFile>& images,
                                    const std::vector<std::size_t>& left,
                                    const std::vector<PhotoCapture>& captures,
                                    std::int64_t tolerance_us);

}  // namespace gport::cli
