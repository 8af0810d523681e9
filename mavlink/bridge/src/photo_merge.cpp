#include "gport/mavlink/bridge/photo_merge.hpp"

namespace gport::mavlink::bridge {

PhotoMerge::Match PhotoMerge::match(Sender sender, std::uint8_t vehicle,
                                    Clock::time_point now) const {
    if (!sender_ || sender == *sender_ || now - at_ > kWindow || now < at_) {
        return Match::kNew;
    }
    if (sender.sysid != vehicle && sender_->sysid != vehicle) {
        return Match::kNew;  // two ground stations' photos: two photos
    }
    return result_ ? Match::kDone : Match::kInFlight;
}

void PhotoMerge::begun(Sender sender, Clock::time_point now) {
    sender_ = sender;
    at_ = now;
    result_.reset();
}

void PhotoMerge::done(std::uint8_t result) {
    result_ = result;
}

PhotoMerge::Clock::duration PhotoMerge::since_begun(Clock::time_point now) const {
    return now - at_;
}

}  // namespace gport::mavlink::bridge
