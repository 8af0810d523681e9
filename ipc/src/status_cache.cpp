#include "gport/ipc/status_cache.hpp"

namespace gport::ipc {

const std::string& StatusCache::members(Clock::time_point now,
                                        const std::function<std::string()>& build) {
    if (!valid_ || now - built_ >= max_age_ || now < built_) {
        text_ = build();
        built_ = now;
        valid_ = true;
        ++builds_;
    }
    return text_;
}

}  // namespace gport::ipc
