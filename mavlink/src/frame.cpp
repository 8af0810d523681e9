#include "gport/mavlink/frame.hpp"

#include <stdexcept>
#include <string>

#include "gport/mavlink/crc.hpp"

namespace gport::mavlink {

std::size_t truncated_length(std::span<const std::uint8_t> payload) {
    std::size_t n = payload.size();
    while (n > 1 && payload[n - 1] == 0) {
        --n;
    }
    return n;
}

Frame Frame::make(const Header& header, std::uint32_t msgid, std::uint8_t crc_extra,
                  std::span<const std::uint8_t> payload, bool signed_frame) {
    if (payload.size() > kMaxPayloadSize) {
        throw std::invalid_argument("MAVLink payload of " + std::to_string(payload.size()) +
                                    " bytes; at most 255");
    }
    if (msgid > kMaxMessageId) {
        throw std::invalid_argument("MAVLink message id " + std::to_string(msgid) +
                                    " does not fit 24 bits");
    }
    const std::size_t len = truncated_length(payload);
    Frame f;
    auto& b = f.bytes_;
    b[0] = kMagicV2;
    b[1] = static_cast<std::uint8_t>(len);
    b[2] = signed_frame ? kIncompatSigned : 0;  // incompat_flags
    b[3] = 0;                                   // compat_flags
    b[4] = header.seq;
    b[5] = header.sysid;
    b[6] = header.compid;
    b[7] = static_cast<std::uint8_t>(msgid & 0xFFU);
    b[8] = static_cast<std::uint8_t>((msgid >> 8) & 0xFFU);
    b[9] = static_cast<std::uint8_t>(msgid >> 16);
    std::copy_n(payload.begin(), len, b.begin() + kHeaderSizeV2);
    std::uint16_t crc = crc_calculate(std::span(b).subspan(1, kHeaderSizeV2 - 1 + len));
    crc = crc_accumulate(crc_extra, crc);
    b[kHeaderSizeV2 + len] = static_cast<std::uint8_t>(crc & 0xFFU);
    b[kHeaderSizeV2 + len + 1] = static_cast<std::uint8_t>(crc >> 8);
    f.size_ = kHeaderSizeV2 + len + kChecksumSize + (signed_frame ? kSignatureSize : 0);
    return f;
}

std::span<std::uint8_t> Frame::signature_block() {
    if (!is_signed()) {
        return {};
    }
    return std::span(bytes_).subspan(size_ - kSignatureSize, kSignatureSize);
}

FrameView Frame::view() const {
    const std::uint32_t msgid =
        std::uint32_t{bytes_[7]} | std::uint32_t{bytes_[8]} << 8 | std::uint32_t{bytes_[9]} << 16;
    return FrameView{{bytes_[4], bytes_[5], bytes_[6]},
                     msgid,
                     {bytes_.data() + kHeaderSizeV2, payload_size()},
                     is_signed(),
                     bytes()};
}

}  // namespace gport::mavlink
