// The camera's image count (MAVLink camera protocol: CAMERA_CAPTURE_STATUS
// image_count; a new image has image_index = image_count - 1, zero-based,
// contiguous), kept across restarts in the state directory's file
// "image-count" beside the signing timestamp, under the same rules
// (signing_files.hpp). Photos only: gportd's capture index also counts
// record toggles (docs/mavlink.md, "Image numbers").
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "gport/mavlink/result.hpp"

namespace gport::mavlink::bridge {

class ImageCount {
  public:
    static constexpr const char* kFileName = "image-count";
    static constexpr std::uint64_t kMax = 0x7fffffff;  // image_count is an int32

    // `directory` empty: not kept (counts from 0 each run).
    explicit ImageCount(const std::string& directory);
    // Checks the directory and reads the file (0 without one); on an error
    // the count is not kept and starts at 0.
    std::optional<Error> load();
    std::int32_t count() const { return count_; }
    // A photo was taken: its image_index (the count before); the count
    // grows by one and is stored; `error` set when it could not be.
    std::int32_t add(std::optional<Error>& error);
    bool kept() const { return !path_.empty(); }
    const std::string& path() const { return path_; }

  private:
    std::string directory_;
    std::string path_;
    std::int32_t count_ = 0;
};

}  // namespace gport::mavlink::bridge
