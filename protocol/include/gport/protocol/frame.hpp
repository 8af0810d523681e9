// G-Port frame layout (all multi-byte fields little-endian):
//
//   offset  size  field
//   0       1     header, always 0xAE
//   1       1     version, 0x01
//   2       1     len: number of data bytes (0..255)
//   3       1     command
//   4       1     hsum = (version + len + command) & 0xFF
//   5       len   data
//   5+len   4     crc32(data), little-endian; ABSENT when len == 0
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>

namespace gport::protocol {

inline constexpr std::uint8_t kFrameHeader = 0xAE;
inline constexpr std::uint8_t kProtocolVersion = 0x01;
inline constexpr std::size_t kHeaderSize = 5;
inline constexpr std::size_t kCrcSize = 4;
inline constexpr std::size_t kMaxDataSize = 255;
inline constexpr std::size_t kMaxFrameSize = kHeaderSize + kMaxDataSize + kCrcSize;
static_assert(kMaxFrameSize == 264);

constexpr std::uint8_t header_sum(std::uint8_t version, std::uint8_t len, std::uint8_t command) {
    return static_cast<std::uint8_t>((unsigned{version} + len + command) & 0xFFU);
}

// Whole frame size on the wire for a data length.
constexpr std::size_t frame_size(std::size_t data_len) {
    return kHeaderSize + data_len + (data_len == 0 ? 0 : kCrcSize);
}

// A decoded frame, borrowed from the decoder: valid only during the callback.
struct FrameView {
    std::uint8_t command = 0;
    std::span<const std::uint8_t> data;
};

// An encoded frame, ready for the wire. Holds its bytes inline: no allocation.
class Frame {
  public:
    // Encodes command + data. Throws std::length_error for more than 255 bytes.
    static Frame make(std::uint8_t command, std::span<const std::uint8_t> data);

    std::span<const std::uint8_t> bytes() const { return {bytes_.data(), size_}; }
    std::uint8_t command() const { return bytes_[3]; }
    std::span<const std::uint8_t> data() const { return {bytes_.data() + kHeaderSize, bytes_[2]}; }
    std::size_t size() const { return size_; }

    friend bool operator==(const Frame& a, const Frame& b) {
        return std::ranges::equal(a.bytes(), b.bytes());
    }

  private:
    std::array<std::uint8_t, kMaxFrameSize> bytes_{};
    std::size_t size_ = 0;
};

}  // namespace gport::protocol
