#include "gport/protocol/frame.hpp"

#include <algorithm>
#include <string>

#include "gport/protocol/crc32.hpp"

namespace gport::protocol {

Frame Frame::make(std::uint8_t command, std::span<const std::uint8_t> data) {
    if (data.size() > kMaxDataSize) {
        throw std::length_error("G-Port frame data is " + std::to_string(data.size()) +
                                " bytes; at most 255 are allowed");
    }
    Frame frame;
    const auto len = static_cast<std::uint8_t>(data.size());
    auto& b = frame.bytes_;
    b[0] = kFrameHeader;
    b[1] = kProtocolVersion;
    b[2] = len;
    b[3] = command;
    b[4] = header_sum(kProtocolVersion, len, command);
    std::ranges::copy(data, b.begin() + kHeaderSize);
    if (len > 0) {
        const std::uint32_t crc = crc32(data);
        std::uint8_t* c = b.data() + kHeaderSize + len;
        for (int i = 0; i < 4; ++i) {
            c[i] = static_cast<std::uint8_t>(crc >> (8 * i));
        }
    }
    frame.size_ = frame_size(len);
    return frame;
}

}  // namespace gport::protocol
