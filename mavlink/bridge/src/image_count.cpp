#include "gport/mavlink/bridge/image_count.hpp"

#include "gport/mavlink/bridge/signing_files.hpp"

namespace gport::mavlink::bridge {

ImageCount::ImageCount(const std::string& directory) : directory_(directory) {}

std::optional<Error> ImageCount::load() {
    path_.clear();
    count_ = 0;
    if (directory_.empty()) {
        return std::nullopt;
    }
    if (auto error = check_state_directory(directory_)) {
        return error;
    }
    const std::string path =
        directory_.back() == '/' ? directory_ + kFileName : directory_ + "/" + kFileName;
    auto stored = load_state_number(path, kMax,
                                    "does not hold an image count (one decimal number up to "
                                    "2^31-1); remove it while gport-mavlink is stopped (the "
                                    "count then starts at 0)");
    if (!stored) {
        return stored.error();
    }
    path_ = path;
    count_ = static_cast<std::int32_t>(*stored);
    return std::nullopt;
}

std::int32_t ImageCount::add(std::optional<Error>& error) {
    const std::int32_t index = count_;
    if (static_cast<std::uint64_t>(count_) < kMax) {
        ++count_;
    }
    if (!path_.empty()) {
        error = save_state_number(path_, static_cast<std::uint64_t>(count_));
    }
    return index;
}

}  // namespace gport::mavlink::bridge
