// libFuzzer target for the frame decoder and the typed-message codec.
//
// Each input is decoded by a naive reference (the decoding rules restated,
// validity judged with Frame::make) and three ways by the decoder: whole (one
// feed() call, so frames are seen in place and can be located in the input),
// byte by byte, and in chunks whose lengths are read from the input itself.
// All must agree exactly. Every frame must be exactly the bytes Frame::make
// gives for its command and data, the counters must add up, the held-back
// tail must stay under one frame, and decoding a frame into a typed message
// must never crash, and must re-encode to the same frame when the length is
// exact.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "gport/protocol/decoder.hpp"
#include "gport/protocol/messages.hpp"

namespace gp = gport::protocol;

namespace {

void require(bool ok, const char* what) {
    if (!ok) {
        std::fprintf(stderr, "decoder_fuzz invariant broken: %s\n", what);
        std::abort();
    }
}

struct Seen {
    std::vector<std::vector<std::uint8_t>> frames;
    gp::DecoderStats stats;
    std::size_t pending = 0;
};

bool same_stats(const gp::DecoderStats& a, const gp::DecoderStats& b) {
    return a.bytes == b.bytes && a.frames == b.frames && a.garbage_bytes == b.garbage_bytes &&
           a.header_errors == b.header_errors && a.crc_errors == b.crc_errors &&
           a.resyncs == b.resyncs;
}

// Lengths of the data field each known command is defined with; the
// re-encoding of a decoded message must be byte-exact for these.
bool exact_length(std::uint8_t cmd, std::size_t len) {
    switch (cmd) {
        case 0x13:
        case 0x16:
            return len == 0;
        case 0x14:
        case 0x15:
            return len == gp::kSettingsSize;
        case 0x85:
            return len == gp::kControlSize;
        case 0x86:
            return len == gp::kCameraSize;
        case 0x87:
            return len == gp::kAttitudeSize || len == gp::kAttitudeWithRatesSize;
        default:
            return true;  // unknown commands are kept whole as RawFrame
    }
}

void check_typed(const gp::FrameView& view, const gp::Frame& frame) {
    const auto msg = gp::decode(view);
    if (!msg.ok()) {
        require(!msg.error().message.empty(), "an error without a message");
        require(msg.error().message.find("0x") != std::string::npos,
                "an error that does not name the command");
        return;
    }
    const gp::Frame again = gp::encode(*msg);
    if (exact_length(view.command, view.data.size())) {
        require(again == frame, "re-encoding a decoded message changed the frame");
    } else {
        // A longer 0x87: the known prefix must round-trip.
        require(view.command == 0x87, "only 0x87 decodes at a length it is not defined with");
        const auto prefix = view.data.first(again.data().size());
        require(std::ranges::equal(again.data(), prefix), "0x87 prefix not preserved");
    }
}

// One feed() of the whole input on a fresh decoder: it scans in place, so each
// frame's data points into `in` and the frame can be checked against its source.
Seen decode_whole(std::span<const std::uint8_t> in) {
    gp::Decoder dec;
    Seen seen;
    std::size_t next_free = 0;  // frames must be in order and must not overlap
    dec.feed(in, [&](const gp::FrameView& view) {
        const gp::Frame frame = gp::Frame::make(view.command, view.data);
        require(view.data.data() >= in.data() + gp::kHeaderSize, "frame data outside input");
        const auto start = static_cast<std::size_t>(view.data.data() - in.data()) - gp::kHeaderSize;
        require(start >= next_free && start + frame.size() <= in.size(), "frame out of place");
        require(std::ranges::equal(frame.bytes(), in.subspan(start, frame.size())),
                "a delivered frame is not the bytes it came from");
        next_free = start + frame.size();
        seen.frames.emplace_back(frame.bytes().begin(), frame.bytes().end());
        check_typed(view, frame);
    });
    seen.stats = dec.stats();
    seen.pending = dec.pending();
    require(seen.pending <= in.size() - next_free, "pending bytes precede the last frame");
    if (seen.pending > 0) {
        require(in[in.size() - seen.pending] == gp::kFrameHeader, "pending tail not at 0xAE");
    }
    return seen;
}

// Feeds `in` in chunks of the lengths `next_len` returns.
template <typename NextLen>
Seen decode_chunked(std::span<const std::uint8_t> in, NextLen next_len) {
    gp::Decoder dec;
    Seen seen;
    std::size_t pos = 0;
    while (pos < in.size()) {
        const std::size_t n = std::min(next_len(pos), in.size() - pos);
        dec.feed(in.subspan(pos, n), [&](const gp::FrameView& view) {
            const gp::Frame frame = gp::Frame::make(view.command, view.data);
            seen.frames.emplace_back(frame.bytes().begin(), frame.bytes().end());
        });
        pos += n;
        require(dec.pending() <= gp::kMaxFrameSize - 1, "pending exceeds one frame");
    }
    seen.stats = dec.stats();
    seen.pending = dec.pending();
    return seen;
}

// The specification, restated as naively as possible: at each 0xAE, the
// candidate is a frame if Frame::make rebuilds exactly its bytes; it is
// rejected if its version or header sum is wrong or the rebuilt frame differs;
// a candidate that cannot be decided yet ends the scan (it is pending). After
// a frame the scan jumps past it; after a rejection it moves on one byte.
Seen decode_reference(std::span<const std::uint8_t> in) {
    Seen seen;
    std::size_t i = 0;
    std::size_t frame_bytes = 0;
    const std::size_t n = in.size();
    while (i < n) {
        if (in[i] != gp::kFrameHeader) {
            ++i;
            continue;
        }
        const std::size_t left = n - i;
        if (left < 2 || (in[i + 1] == gp::kProtocolVersion && left < gp::kHeaderSize)) {
            break;  // undecided
        }
        if (in[i + 1] != gp::kProtocolVersion ||
            gp::header_sum(in[i + 1], in[i + 2], in[i + 3]) != in[i + 4]) {
            ++seen.stats.header_errors;
            ++i;
            continue;
        }
        const std::size_t size = gp::frame_size(in[i + 2]);
        if (left < size) {
            break;  // undecided
        }
        const gp::Frame f = gp::Frame::make(in[i + 3], in.subspan(i + gp::kHeaderSize, in[i + 2]));
        if (!std::ranges::equal(f.bytes(), in.subspan(i, size))) {
            ++seen.stats.crc_errors;
            ++i;
            continue;
        }
        seen.frames.emplace_back(f.bytes().begin(), f.bytes().end());
        frame_bytes += size;
        i += size;
    }
    seen.pending = n - i;
    seen.stats.bytes = n;
    seen.stats.frames = seen.frames.size();
    seen.stats.garbage_bytes = n - frame_bytes - seen.pending;
    return seen;
}

void check_counters(const Seen& s, std::size_t input_size) {
    std::size_t frame_bytes = 0;
    for (const auto& f : s.frames) {
        frame_bytes += f.size();
    }
    require(s.stats.bytes == input_size, "bytes counter");
    require(s.stats.frames == s.frames.size(), "frames counter");
    require(s.stats.garbage_bytes + frame_bytes + s.pending == input_size,
            "garbage + frames + pending != bytes fed");
    // Each rejected candidate discards exactly its 0xAE byte.
    require(s.stats.header_errors + s.stats.crc_errors <= s.stats.garbage_bytes,
            "more rejections than garbage bytes");
    require(s.stats.resyncs <= s.stats.frames, "more resyncs than frames");
    require(s.pending <= gp::kMaxFrameSize - 1, "pending exceeds one frame");
}

void require_same(const Seen& a, const Seen& b, const char* what) {
    require(a.frames == b.frames, what);
    require(same_stats(a.stats, b.stats), what);
    require(a.pending == b.pending, what);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::span<const std::uint8_t> in(data, size);
    const Seen whole = decode_whole(in);
    check_counters(whole, size);

    const Seen reference = decode_reference(in);
    require(whole.frames == reference.frames, "frames differ from the reference decoder");
    require(whole.pending == reference.pending, "pending differs from the reference decoder");
    require(whole.stats.garbage_bytes == reference.stats.garbage_bytes &&
                whole.stats.header_errors == reference.stats.header_errors &&
                whole.stats.crc_errors == reference.stats.crc_errors,
            "counters differ from the reference decoder");

    const Seen bytewise = decode_chunked(in, [](std::size_t) { return std::size_t{1}; });
    require_same(whole, bytewise, "byte-by-byte feeding differs from whole");

    // Chunk lengths 1..300 taken from the input, so the fuzzer explores splits too.
    const Seen split = decode_chunked(in, [&](std::size_t pos) {
        const std::size_t a = in[(pos * 7 + 3) % size];
        const std::size_t b = in[(pos * 13 + 5) % size];
        return 1 + (a << 8 | b) % 300;
    });
    require_same(whole, split, "split feeding differs from whole");
    return 0;
}
