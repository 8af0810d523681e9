// The camera's CAMERA_IMAGE_CAPTURED messages kept for a ground station that
// missed one (the camera protocol: MAV_CMD_REQUEST_MESSAGE with param1 263,
// param2 the first image_index or -1 for all, param3 0 for that one, -1 for
// it and all after, else the last image_index). The newest kImageHistory
// photos of this run, each as it was first sent (the same position, time
// and orientation: gportd's capture is its one source), in memory: after a
// restart only the new ones (docs/mavlink.md, "The camera component").
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <vector>

#include "gport/mavlink/messages.hpp"

namespace gport::mavlink::bridge {

inline constexpr std::size_t kImageHistory = 1024;
// At most this many messages in answer to one request (the rest is asked
// again from the next index), and at most this many re-sent a second: a
// request for every image cannot flood the link it came by.
inline constexpr std::size_t kImageResendBatch = 64;
inline constexpr double kImageResendPerSecond = 128;

// The image indexes a REQUEST_MESSAGE(263) asks for: [first, last], last
// empty for "to the newest". Empty when param2 or param3 is not one of the
// values above (a fraction, NaN, below -1, a last before the first).
struct ImageRange {
    std::int32_t first = 0;
    std::optional<std::int32_t> last{};
};
std::optional<ImageRange> image_range(const CommandLong& command);

class ImageHistory {
  public:
    explicit ImageHistory(std::size_t capacity = kImageHistory) : capacity_(capacity) {}
    // A photo's message as sent (a failed photo's, image_index -1, is not kept).
    void add(const CameraImageCaptured& message);
    // The kept messages within `range`, oldest first, at most `limit`.
    std::vector<CameraImageCaptured> find(const ImageRange& range, std::size_t limit) const;
    std::size_t size() const { return held_.size(); }

  private:
    std::size_t capacity_;
    std::deque<CameraImageCaptured> held_;  // image_index ascending
};

}  // namespace gport::mavlink::bridge
