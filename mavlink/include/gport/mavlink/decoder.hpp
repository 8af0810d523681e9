// Streaming MAVLink 2 decoder: a pure, byte-fed state machine.
//
// Feed it bytes in any chunking; it calls the sink once per valid MAVLink 2
// frame of a message this codec knows (messages.hpp), in order. It owns no
// I/O, logs nothing and allocates nothing: its state is a fixed buffer of at
// most one partial frame.
//
// A candidate starts at 0xFD (MAVLink 2) or 0xFE (MAVLink 1). It is rejected,
// in this order, when: an incompat flag other than "signed" is set (header
// error; the spec says such frames must be dropped); its message id is not
// one this codec knows (unknown id: without the CRC_EXTRA its checksum
// cannot be checked); its length exceeds the message's full length (length
// error; a MAVLink 1 frame's must equal the base length); its checksum is
// wrong (CRC error). A rejected candidate is re-scanned from its SECOND byte,
// so no valid frame is lost because of what came before it: a false start
// byte whose claimed length swallows a real frame only delays that frame
// until the claim is disproved.
//
// An autopilot sends many messages this codec does not decode. Such a frame
// (a candidate with an unknown id) casts a shadow as long as its header
// claims: the bytes in it are counted as unknown_bytes, not garbage, and
// the candidates that start inside it are not counted as header, length or
// CRC errors (they are bytes of that frame's payload, not malformed
// frames). They are still scanned, so a real frame is never lost to a
// false start that happens to carry an unknown id: a frame found inside a
// shadow ends it.
//
// Decisions (docs/mavlink.md):
//   - MAVLink 1 frames are recognised (valid checksum, known id, exact
//     length), skipped whole and counted in v1_frames; never delivered.
//   - A signed MAVLink 2 frame is delivered with is_signed set and its
//     13-byte signature in `bytes`; the decoder does not verify it (that
//     needs the key: signing.hpp's Verifier, which gport-mavlink applies to
//     every frame before acting on it).
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>

#include "gport/base/carry_buffer.hpp"
#include "gport/mavlink/frame.hpp"

namespace gport::mavlink {

struct DecoderStats {
    std::uint64_t bytes = 0;          // bytes fed
    std::uint64_t frames = 0;         // MAVLink 2 frames delivered
    std::uint64_t signed_frames = 0;  // of those, signed (signature not checked here)
    std::uint64_t v1_frames = 0;      // valid MAVLink 1 frames skipped
    std::uint64_t v1_bytes = 0;       // their bytes
    std::uint64_t garbage_bytes = 0;  // bytes discarded (not part of any valid frame)
    std::uint64_t header_errors = 0;  // candidates with unknown incompat flags
    std::uint64_t unknown_ids = 0;    // frames of ids this codec does not know (shadows cast)
    std::uint64_t unknown_bytes = 0;  // bytes in their shadows (not garbage)
    std::uint64_t length_errors = 0;  // candidates longer than their message allows
    std::uint64_t crc_errors = 0;     // candidates with a wrong checksum
    std::uint64_t resyncs = 0;        // frames (v1 or v2) that ended a run of garbage
};

class Decoder {
  public:
    // Feeds bytes; calls sink(const FrameView&) for every valid MAVLink 2 frame.
    template <typename Sink>
    void feed(std::span<const std::uint8_t> input, Sink&& sink);

    const DecoderStats& stats() const { return stats_; }
    // Bytes held back as the start of a possible frame (< kMaxFrameSize).
    std::size_t pending() const { return carry_.held(); }
    // Forgets any partial frame (e.g. after the link was reopened); keeps stats.
    void reset();

  private:
    enum class Verdict { kFrame, kV1Frame, kNeedMore, kHeader, kUnknownId, kLength, kCrc };
    // Judges the candidate at p[0] (0xFD or 0xFE) with n bytes available;
    // sets size (whole frame) and, for kFrame, view.
    static Verdict check(const std::uint8_t* p, std::size_t n, std::size_t& size, FrameView& view);
    static Verdict check_v1(const std::uint8_t* p, std::size_t n, std::size_t& size);

    template <typename Sink>
    std::size_t scan(const std::uint8_t* p, std::size_t n, Sink& sink);
    void discard(std::size_t count);
    void reject(Verdict why, std::size_t size);
    void accepted();

    static constexpr std::size_t kBufferSize = 2 * kMaxFrameSize;
    base::CarryBuffer<kBufferSize> carry_;
    bool in_garbage_ = false;
    std::size_t shadow_ = 0;  // bytes left of an unknown-id frame's claimed span
    DecoderStats stats_{};
};

// ---- implementation --------------------------------------------------------

constexpr bool is_magic(std::uint8_t b) {
    return b == kMagicV2 || b == kMagicV1;
}

// Scans p[0..n): delivers frames, discards garbage, and returns how many bytes
// were consumed; the rest (an undecided candidate) must be offered again with
// more bytes after it.
template <typename Sink>
std::size_t Decoder::scan(const std::uint8_t* p, std::size_t n, Sink& sink) {
    std::size_t i = 0;
    while (i < n) {
        if (!is_magic(p[i])) {
            const auto* next = std::find_if(p + i, p + n, is_magic);
            const auto skipped = static_cast<std::size_t>(next - (p + i));
            discard(skipped);
            i += skipped;
            continue;
        }
        std::size_t size = 0;
        FrameView view;
        const Verdict verdict = check(p + i, n - i, size, view);
        switch (verdict) {
            case Verdict::kNeedMore:
                return i;
            case Verdict::kFrame:
                ++stats_.frames;
                stats_.signed_frames += view.is_signed ? 1 : 0;
                accepted();
                sink(static_cast<const FrameView&>(view));
                i += size;
                break;
            case Verdict::kV1Frame:
                ++stats_.v1_frames;
                stats_.v1_bytes += size;
                accepted();
                i += size;
                break;
            default:
                reject(verdict, size);
                discard(1);  // re-scan from the candidate's second byte
                ++i;
                break;
        }
    }
    return i;
}

template <typename Sink>
void Decoder::feed(std::span<const std::uint8_t> input, Sink&& sink) {
    stats_.bytes += input.size();
    carry_.feed(input, [&](const std::uint8_t* p, std::size_t n) { return scan(p, n, sink); });
}

}  // namespace gport::mavlink
