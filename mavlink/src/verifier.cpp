#include "gport/mavlink/verifier.hpp"

#include <algorithm>
#include <stdexcept>

namespace gport::mavlink {

std::string_view to_string(SignatureCheck check) {
    switch (check) {
        case SignatureCheck::kAccepted:
            return "accepted";
        case SignatureCheck::kUnsigned:
            return "unsigned";
        case SignatureCheck::kBadSignature:
            return "bad signature";
        case SignatureCheck::kReplayed:
            return "replayed";
        case SignatureCheck::kTooOld:
            return "too old";
        case SignatureCheck::kStreamsFull:
            return "stream table full";
    }
    return "unknown";
}

Verifier::Verifier(SecretKey key, std::size_t max_streams)
    : key_(std::move(key)), max_streams_(max_streams) {
    if (max_streams_ == 0) {
        throw std::invalid_argument("Verifier: a stream table of 0 entries accepts nothing");
    }
    streams_.reserve(max_streams_);
}

Verdict Verifier::check(std::span<const std::uint8_t> frame, std::uint64_t local) {
    if (frame.size() < kHeaderSizeV2 || (frame[2] & kIncompatSigned) == 0) {
        return {SignatureCheck::kUnsigned, 0};
    }
    const auto block = signature_block_of(frame);
    if (!block || !signature_matches(key_, frame, *block)) {
        return {SignatureCheck::kBadSignature, block ? block->timestamp : 0};
    }
    const StreamKey key{frame[5], frame[6], block->link_id};
    const auto known = std::ranges::find(streams_, key, &Stream::key);
    if (known == streams_.end()) {
        return admit_new(key, block->timestamp, local);
    }
    if (block->timestamp <= known->last) {
        return {SignatureCheck::kReplayed, block->timestamp};
    }
    known->last = block->timestamp;
    return {SignatureCheck::kAccepted, block->timestamp};
}

Verdict Verifier::admit_new(const StreamKey& key, std::uint64_t timestamp, std::uint64_t local) {
    const auto stale = [local](std::uint64_t t) { return t + kOneMinute < local; };
    if (stale(timestamp)) {
        return {SignatureCheck::kTooOld, timestamp};
    }
    if (streams_.size() == max_streams_) {
        const auto victim =
            std::ranges::find_if(streams_, [&](const Stream& s) { return stale(s.last); });
        if (victim == streams_.end()) {
            return {SignatureCheck::kStreamsFull, timestamp};
        }
        streams_.erase(victim);
    }
    streams_.push_back({key, timestamp});
    return {SignatureCheck::kAccepted, timestamp};
}

}  // namespace gport::mavlink
