#include "gport/mavlink/decoder.hpp"

#include <algorithm>

#include "gport/mavlink/crc.hpp"
#include "gport/mavlink/messages.hpp"

namespace gport::mavlink {
namespace {

// The checksum at p[covered + 1], little-endian, against X.25 over
// p[1..covered] and the CRC_EXTRA.
bool checksum_ok(const std::uint8_t* p, std::size_t covered, std::uint8_t crc_extra) {
    std::uint16_t crc = crc_calculate({p + 1, covered});
    crc = crc_accumulate(crc_extra, crc);
    const auto wire = static_cast<std::uint16_t>(p[covered + 1] | p[covered + 2] << 8);
    return crc == wire;
}

}  // namespace

void Decoder::reset() {
    discard(carry_.clear());
}

void Decoder::discard(std::size_t count) {
    const std::size_t shadowed = std::min(count, shadow_);
    shadow_ -= shadowed;
    stats_.unknown_bytes += shadowed;
    stats_.garbage_bytes += count - shadowed;
    if (count > shadowed) {
        in_garbage_ = true;
    }
}

void Decoder::accepted() {
    shadow_ = 0;  // a real frame: the claim that covered it was false
    if (in_garbage_) {
        ++stats_.resyncs;
        in_garbage_ = false;
    }
}

void Decoder::reject(Verdict why, std::size_t size) {
    if (shadow_ > 0) {
        return;  // a candidate inside an unknown frame: its payload's bytes
    }
    switch (why) {
        case Verdict::kHeader:
            ++stats_.header_errors;
            break;
        case Verdict::kUnknownId:
            ++stats_.unknown_ids;
            shadow_ = size;
            break;
        case Verdict::kLength:
            ++stats_.length_errors;
            break;
        case Verdict::kCrc:
            ++stats_.crc_errors;
            break;
        default:
            break;
    }
}

Decoder::Verdict Decoder::check_v1(const std::uint8_t* p, std::size_t n, std::size_t& size) {
    if (n < kHeaderSizeV1) {
        return Verdict::kNeedMore;
    }
    const std::size_t len = p[1];
    const MessageInfo* info = find_message(p[5]);
    if (info == nullptr) {
        size = kHeaderSizeV1 + len + kChecksumSize;
        return Verdict::kUnknownId;
    }
    if (len != info->base_length) {
        return Verdict::kLength;
    }
    size = kHeaderSizeV1 + len + kChecksumSize;
    if (n < size) {
        return Verdict::kNeedMore;
    }
    return checksum_ok(p, kHeaderSizeV1 - 1 + len, info->crc_extra) ? Verdict::kV1Frame
                                                                    : Verdict::kCrc;
}

Decoder::Verdict Decoder::check(const std::uint8_t* p, std::size_t n, std::size_t& size,
                                FrameView& view) {
    if (p[0] == kMagicV1) {
        return check_v1(p, n, size);
    }
    if (n >= 3 && (p[2] & ~kIncompatSigned) != 0) {
        return Verdict::kHeader;
    }
    if (n < kHeaderSizeV2) {
        return Verdict::kNeedMore;
    }
    const std::uint32_t msgid =
        std::uint32_t{p[7]} | std::uint32_t{p[8]} << 8 | std::uint32_t{p[9]} << 16;
    const MessageInfo* info = find_message(msgid);
    const std::size_t len = p[1];
    const bool is_signed = (p[2] & kIncompatSigned) != 0;
    size = kHeaderSizeV2 + len + kChecksumSize + (is_signed ? kSignatureSize : 0);
    if (info == nullptr) {
        return Verdict::kUnknownId;
    }
    if (len > info->full_length) {
        return Verdict::kLength;
    }
    if (n < size) {
        return Verdict::kNeedMore;
    }
    if (!checksum_ok(p, kHeaderSizeV2 - 1 + len, info->crc_extra)) {
        return Verdict::kCrc;
    }
    view = FrameView{{p[4], p[5], p[6]}, msgid, {p + kHeaderSizeV2, len}, is_signed, {p, size}};
    return Verdict::kFrame;
}

}  // namespace gport::mavlink
