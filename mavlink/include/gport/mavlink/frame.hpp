// MAVLink 2 frame layout (multi-byte fields little-endian):
//
//   offset  size  field
//   0       1     magic, 0xFD (0xFE starts a MAVLink 1 frame, see below)
//   1       1     len: payload bytes (0..255), after trailing-zero truncation
//   2       1     incompat_flags: 0x01 = signed; any other bit set = reject
//   3       1     compat_flags: ignored
//   4       1     seq
//   5       1     sysid
//   6       1     compid
//   7       3     msgid (24 bit)
//   10      len   payload
//   10+len  2     checksum: X.25 over bytes 1..9+len, then CRC_EXTRA
//   12+len  13    signature, only when incompat_flags has 0x01
//
// MAVLink 1 (not delivered; the decoder recognises and counts them):
//   0 magic 0xFE, 1 len, 2 seq, 3 sysid, 4 compid, 5 msgid (8 bit),
//   6 payload, 6+len checksum (over bytes 1..5+len, then CRC_EXTRA).
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace gport::mavlink {

inline constexpr std::uint8_t kMagicV2 = 0xFD;
inline constexpr std::uint8_t kMagicV1 = 0xFE;
inline constexpr std::uint8_t kIncompatSigned = 0x01;
inline constexpr std::size_t kHeaderSizeV2 = 10;
inline constexpr std::size_t kHeaderSizeV1 = 6;
inline constexpr std::size_t kChecksumSize = 2;
inline constexpr std::size_t kSignatureSize = 13;
inline constexpr std::size_t kMaxPayloadSize = 255;
inline constexpr std::size_t kMaxFrameSize =
    kHeaderSizeV2 + kMaxPayloadSize + kChecksumSize + kSignatureSize;
static_assert(kMaxFrameSize == 280);
inline constexpr std::uint32_t kMaxMessageId = 0xFFFFFF;

// Who sends a frame, and its sequence number.
struct Header {
    std::uint8_t seq = 0;
    std::uint8_t sysid = 0;
    std::uint8_t compid = 0;
    friend bool operator==(const Header&, const Header&) = default;
};

// A valid MAVLink 2 frame, borrowed from the decoder: valid only during the
// callback. The payload is as received (possibly truncated).
struct FrameView {
    Header header;
    std::uint32_t msgid = 0;
    std::span<const std::uint8_t> payload;
    bool is_signed = false;  // carries a signature (the decoder does not verify it)
    // The whole frame as received, from the magic byte to the end of the
    // checksum, or of the signature when signed (what a verifier needs).
    std::span<const std::uint8_t> bytes{};
};

// An encoded MAVLink 2 frame: unsigned, or signed with room for the
// 13-byte signature block that a signer (signing.hpp) fills in.
class Frame {
  public:
    // Builds the frame, dropping the payload's trailing zero bytes (MAVLink
    // 2 truncation; the first byte is always kept). With `signed_frame` the
    // incompat flag 0x01 is set (the checksum covers it) and a zeroed
    // signature block follows the checksum. Throws std::invalid_argument for
    // a payload over 255 bytes or an id over 24 bits (programming errors:
    // the codec never builds those).
    static Frame make(const Header& header, std::uint32_t msgid, std::uint8_t crc_extra,
                      std::span<const std::uint8_t> payload, bool signed_frame = false);

    std::span<const std::uint8_t> bytes() const { return {bytes_.data(), size_}; }
    std::size_t size() const { return size_; }
    bool is_signed() const { return (bytes_[2] & kIncompatSigned) != 0; }
    std::size_t payload_size() const { return bytes_[1]; }
    // A signed frame's signature block (link id, timestamp, signature);
    // empty for an unsigned one.
    std::span<std::uint8_t> signature_block();
    // The frame as the decoder would deliver it.
    FrameView view() const;

    friend bool operator==(const Frame& a, const Frame& b) {
        return std::ranges::equal(a.bytes(), b.bytes());
    }

  private:
    std::array<std::uint8_t, kMaxFrameSize> bytes_{};
    std::size_t size_ = 0;
};

// The payload length once trailing zeros are dropped (at least 1 byte).
std::size_t truncated_length(std::span<const std::uint8_t> payload);

}  // namespace gport::mavlink
