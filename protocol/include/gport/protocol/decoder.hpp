// Streaming G-Port frame decoder: a pure, byte-fed state machine.
//
// Feed it bytes in any chunking; it calls the sink once per valid frame, in
// order. It owns no I/O, logs nothing and allocates nothing: its state is a
// fixed buffer of at most one partial frame.
//
// A candidate frame starts at an 0xAE byte. It is rejected when its version
// is not 0x01, its header sum is wrong, or (last) its CRC is wrong. A
// rejected candidate is re-scanned from its SECOND byte, so no valid frame is
// lost because of what came before it — a false 0xAE whose claimed length
// swallows a real frame only delays that frame until the claim is disproved.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>

#include "gport/base/carry_buffer.hpp"
#include "gport/protocol/crc32.hpp"
#include "gport/protocol/frame.hpp"

namespace gport::protocol {

struct DecoderStats {
    std::uint64_t bytes = 0;          // bytes fed
    std::uint64_t frames = 0;         // valid frames delivered
    std::uint64_t garbage_bytes = 0;  // bytes discarded (not part of a delivered frame)
    std::uint64_t header_errors = 0;  // candidates rejected: bad version or header sum
    std::uint64_t crc_errors = 0;     // candidates rejected: bad CRC
    std::uint64_t resyncs = 0;        // valid frames that ended a run of discarded bytes
};

class Decoder {
  public:
    // Feeds bytes; calls sink(const FrameView&) for every complete valid frame.
    template <typename Sink>
    void feed(std::span<const std::uint8_t> input, Sink&& sink);

    const DecoderStats& stats() const { return stats_; }
    // Bytes held back as the start of a possible frame (at most kMaxFrameSize - 1).
    std::size_t pending() const { return carry_.held(); }
    // Forgets any partial frame (e.g. after the device was reopened); keeps stats.
    void reset();

  private:
    enum class Verdict { kFrame, kReject, kNeedMore };
    static Verdict check(const std::uint8_t* p, std::size_t n, std::size_t& size, bool& crc_bad);

    template <typename Sink>
    std::size_t scan(const std::uint8_t* p, std::size_t n, Sink& sink);
    void discard(std::size_t count);
    std::size_t skip_garbage(const std::uint8_t* p, std::size_t i, std::size_t n);

    static constexpr std::size_t kBufferSize = 2 * kMaxFrameSize;
    base::CarryBuffer<kBufferSize> carry_;
    bool in_garbage_ = false;
    DecoderStats stats_{};
};

// ---- implementation --------------------------------------------------------

inline void Decoder::reset() {
    discard(carry_.clear());
}

inline void Decoder::discard(std::size_t count) {
    stats_.garbage_bytes += count;
    if (count > 0) {
        in_garbage_ = true;
    }
}

// Judges the candidate at p[0] == 0xAE with n bytes available.
inline Decoder::Verdict Decoder::check(const std::uint8_t* p, std::size_t n, std::size_t& size,
                                       bool& crc_bad) {
    crc_bad = false;
    if (n < 2) {
        return Verdict::kNeedMore;
    }
    if (p[1] != kProtocolVersion) {
        return Verdict::kReject;
    }
    if (n < kHeaderSize) {
        return Verdict::kNeedMore;
    }
    const std::uint8_t len = p[2];
    if (header_sum(p[1], len, p[3]) != p[4]) {
        return Verdict::kReject;
    }
    size = frame_size(len);
    if (n < size) {
        return Verdict::kNeedMore;
    }
    if (len > 0) {
        const std::uint8_t* c = p + kHeaderSize + len;
        const std::uint32_t wire =
            static_cast<std::uint32_t>(c[0]) | static_cast<std::uint32_t>(c[1]) << 8 |
            static_cast<std::uint32_t>(c[2]) << 16 | static_cast<std::uint32_t>(c[3]) << 24;
        if (crc32({p + kHeaderSize, len}) != wire) {
            crc_bad = true;
            return Verdict::kReject;
        }
    }
    return Verdict::kFrame;
}

namespace detail {
// 0x80 in every byte of x that is zero, 0 elsewhere (exact: no borrows).
constexpr std::uint64_t zero_bytes(std::uint64_t x) {
    constexpr std::uint64_t kLow7 = 0x7F7F7F7F7F7F7F7FULL;
    return ~(((x & kLow7) + kLow7) | x | kLow7);
}
inline std::uint64_t load64(const std::uint8_t* p) {
    std::uint64_t v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
}  // namespace detail

// Skips, from p[i], the bytes that cannot start a frame: every byte that is
// not 0xAE, and every 0xAE not followed by the version (a header error, as
// check() would find). Eight bytes per step, without a branch per byte, so
// garbage dense in 0xAE costs no mispredicted branches; stops at an 0xAE 0x01
// pair, or, near the end, at any 0xAE (check() decides whether it is a
// candidate or must wait for more bytes).
inline std::size_t Decoder::skip_garbage(const std::uint8_t* p, std::size_t i, std::size_t n) {
    static_assert(std::endian::native == std::endian::little);
    constexpr std::uint64_t kHeaders = 0x0101010101010101ULL * kFrameHeader;
    constexpr std::uint64_t kVersions = 0x0101010101010101ULL * kProtocolVersion;
    const std::size_t start = i;
    std::uint64_t version_errors = 0;
    while (i + 9 <= n) {
        const std::uint64_t headers = detail::zero_bytes(detail::load64(p + i) ^ kHeaders);
        const std::uint64_t versions = detail::zero_bytes(detail::load64(p + i + 1) ^ kVersions);
        const std::uint64_t candidates = headers & versions;
        if (candidates != 0) {
            const int bit = std::countr_zero(candidates) - 7;  // first bit of that byte
            const std::uint64_t before = (std::uint64_t{1} << bit) - 1;
            version_errors += static_cast<std::uint64_t>(std::popcount(headers & before));
            i += static_cast<std::size_t>(bit) / 8;
            stats_.header_errors += version_errors;
            discard(i - start);
            return i;
        }
        version_errors += static_cast<std::uint64_t>(std::popcount(headers));
        i += 8;
    }
    while (i < n && p[i] != kFrameHeader) {
        ++i;
    }
    stats_.header_errors += version_errors;
    discard(i - start);
    return i;
}

// Scans p[0..n): delivers frames, discards garbage, and returns how many bytes
// were consumed; the rest (an incomplete candidate) must be offered again
// with more bytes after it.
template <typename Sink>
std::size_t Decoder::scan(const std::uint8_t* p, std::size_t n, Sink& sink) {
    std::size_t i = 0;
    while (i < n) {
        if (p[i] != kFrameHeader || (i + 1 < n && p[i + 1] != kProtocolVersion)) {
            i = skip_garbage(p, i, n);
            if (i == n) {
                break;
            }
        }
        std::size_t size = 0;
        bool crc_bad = false;
        switch (check(p + i, n - i, size, crc_bad)) {
            case Verdict::kNeedMore:
                return i;
            case Verdict::kReject:
                ++(crc_bad ? stats_.crc_errors : stats_.header_errors);
                discard(1);  // re-scan from the candidate's second byte
                ++i;
                break;
            case Verdict::kFrame: {
                ++stats_.frames;
                if (in_garbage_) {
                    ++stats_.resyncs;
                    in_garbage_ = false;
                }
                sink(FrameView{p[i + 3], {p + i + kHeaderSize, p[i + 2]}});
                i += size;
                break;
            }
        }
    }
    return i;
}

template <typename Sink>
void Decoder::feed(std::span<const std::uint8_t> input, Sink&& sink) {
    stats_.bytes += input.size();
    carry_.feed(input, [&](const std::uint8_t* p, std::size_t n) { return scan(p, n, sink); });
}

}  // namespace gport::protocol
