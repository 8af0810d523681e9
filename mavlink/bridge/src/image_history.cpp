// CAMERA_IMAGE_CAPTURED kept for a re-request (image_history.hpp).
#include "gport/mavlink/bridge/image_history.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gport::mavlink::bridge {

namespace {

// A whole number from -1 to INT32_MAX, as a float param carries it.
std::optional<std::int32_t> index_param(float value) {
    if (!std::isfinite(value) || value != std::floor(value) || value < -1 ||
        value > static_cast<float>(std::numeric_limits<std::int32_t>::max())) {
        return std::nullopt;
    }
    // A float reaches 2^31 only at the top, past INT32_MAX: clamped.
    return static_cast<std::int32_t>(
        std::min<double>(value, std::numeric_limits<std::int32_t>::max()));
}

}  // namespace

std::optional<ImageRange> image_range(const CommandLong& command) {
    const auto first = index_param(command.param[1]);
    const auto last = index_param(command.param[2]);
    if (!first || !last) {
        return std::nullopt;
    }
    if (*first == -1) {
        return ImageRange{0, std::nullopt};  // every image
    }
    if (*last == 0) {
        return ImageRange{*first, *first};
    }
    if (*last == -1) {
        return ImageRange{*first, std::nullopt};
    }
    if (*last < *first) {
        return std::nullopt;
    }
    return ImageRange{*first, *last};
}

void ImageHistory::add(const CameraImageCaptured& message) {
    if (message.image_index < 0) {
        return;
    }
    // The count is contiguous and only grows; one kept from an earlier
    // count (its file lost, the count restarted) would break the order.
    while (!held_.empty() && held_.back().image_index >= message.image_index) {
        held_.pop_back();
    }
    held_.push_back(message);
    if (held_.size() > capacity_) {
        held_.pop_front();
    }
}

std::vector<CameraImageCaptured> ImageHistory::find(const ImageRange& range,
                                                    std::size_t limit) const {
    const auto begin = std::lower_bound(
        held_.begin(), held_.end(), range.first,
        [](const CameraImageCaptured& m, std::int32_t index) { return m.image_index < index; });
    std::vector<CameraImageCaptured> found;
    for (auto it = begin; it != held_.end() && found.size() < limit; ++it) {
        if (range.last && it->image_index > *range.last) {
            break;
        }
        found.push_back(*it);
    }
    return found;
}

}  // namespace gport::mavlink::bridge
