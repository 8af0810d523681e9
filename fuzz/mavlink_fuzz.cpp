// libFuzzer target for the MAVLink 2 codec (mavlink/).
//
// Each input is decoded three ways, whole, byte by byte and in chunks whose
// lengths come from the input; all must agree on the frames and counters.
// Every delivered frame must decode into a typed message, and re-encoding
// that message must give the delivered payload minus its trailing zeros
// (MAVLink 2 truncation) and decode back to the same bits. The counters must
// (garbage, unknown-id shadows, frames, MAVLink 1, pending) add up to the
// bytes fed and the held-back tail must stay under one frame.
// Then the input is read as a payload of one of the known messages (its
// first byte picks which): decoded, encoded, and fed to a fresh decoder, it
// must come back as exactly one frame with the same bits.
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <vector>

#include "gport/mavlink/decoder.hpp"
#include "gport/mavlink/messages.hpp"

namespace gm = gport::mavlink;

namespace {

void require(bool ok, const char* what) {
    if (!ok) {
        std::fprintf(stderr, "mavlink_fuzz invariant broken: %s\n", what);
        std::abort();
    }
}

struct Seen {
    std::vector<std::vector<std::uint8_t>> payloads;
    std::vector<std::uint32_t> ids;
    gm::DecoderStats stats;
    std::size_t pending = 0;
    std::size_t frame_bytes = 0;
};

bool same_stats(const gm::DecoderStats& a, const gm::DecoderStats& b) {
    return a.bytes == b.bytes && a.frames == b.frames && a.signed_frames == b.signed_frames &&
           a.v1_frames == b.v1_frames && a.v1_bytes == b.v1_bytes &&
           a.garbage_bytes == b.garbage_bytes && a.header_errors == b.header_errors &&
           a.unknown_ids == b.unknown_ids && a.unknown_bytes == b.unknown_bytes &&
           a.length_errors == b.length_errors && a.crc_errors == b.crc_errors &&
           a.resyncs == b.resyncs;
}

void check_frame(const gm::FrameView& view) {
    const auto msg = gm::decode(view);
    require(msg.ok(), "a delivered frame does not decode");
    require(gm::id_of(*msg) == view.msgid, "decoded id differs");
    const gm::Frame again = gm::encode(*msg, view.header);
    // MAVLink 2 never truncates the first byte: an empty payload (which the
    // decoder accepts, as all zeros) comes back as one zero byte.
    const std::size_t kept = gm::truncated_length(view.payload);
    const bool as_sent =
        view.payload.empty()
            ? std::ranges::equal(again.view().payload, std::array<std::uint8_t, 1>{})
            : std::ranges::equal(again.view().payload, view.payload.first(kept));
    require(as_sent, "re-encoding changed the payload beyond its trailing zeros");
    const auto back = gm::decode(again.view());
    require(back.ok() && gm::same_bits(*back, *msg), "re-encoded frame decodes differently");
}

template <typename NextLen>
Seen decode_chunked(std::span<const std::uint8_t> in, NextLen next_len, bool check) {
    gm::Decoder dec;
    Seen seen;
    std::size_t pos = 0;
    while (pos < in.size()) {
        const std::size_t n = std::min(next_len(pos), in.size() - pos);
        dec.feed(in.subspan(pos, n), [&](const gm::FrameView& view) {
            seen.payloads.emplace_back(view.payload.begin(), view.payload.end());
            seen.ids.push_back(view.msgid);
            seen.frame_bytes += gm::kHeaderSizeV2 + view.payload.size() + gm::kChecksumSize +
                                (view.is_signed ? gm::kSignatureSize : 0);
            if (check) {
                check_frame(view);
            }
        });
        pos += n;
        require(dec.pending() < gm::kMaxFrameSize, "pending exceeds one frame");
    }
    seen.stats = dec.stats();
    seen.pending = dec.pending();
    return seen;
}

void check_counters(const Seen& s, std::size_t input_size) {
    const auto& st = s.stats;
    require(st.bytes == input_size, "bytes counter");
    require(st.frames == s.payloads.size(), "frames counter");
    // An unknown id's frame is neither garbage nor delivered: its bytes are
    // unknown_bytes (the decoder's "shadow").
    require(
        st.garbage_bytes + st.unknown_bytes + s.frame_bytes + st.v1_bytes + s.pending == input_size,
        "garbage + unknown + frames + v1 + pending != bytes fed");
    require(st.header_errors + st.unknown_ids + st.length_errors + st.crc_errors <=
                st.garbage_bytes + st.unknown_bytes,
            "more rejections than garbage and unknown bytes");
    require(st.resyncs <= st.frames + st.v1_frames, "more resyncs than frames");
    require(st.signed_frames <= st.frames, "more signed frames than frames");
}

void require_same(const Seen& a, const Seen& b, const char* what) {
    require(a.payloads == b.payloads && a.ids == b.ids, what);
    require(same_stats(a.stats, b.stats), what);
    require(a.pending == b.pending, what);
}

// The input as the payload of a known message, through encode and decode.
void round_trip(std::span<const std::uint8_t> in) {
    if (in.empty()) {
        return;
    }
    const auto table = gm::message_table();
    const gm::MessageInfo& info = table[in[0] % table.size()];
    const auto payload = in.subspan(1, std::min(in.size() - 1, info.full_length));
    const auto msg = gm::decode({{in[0], 1, 154}, info.id, payload, false});
    require(msg.ok(), "a payload within the full length does not decode");
    const gm::Frame frame = gm::encode(*msg, {in[0], 1, 154});
    gm::Decoder dec;
    int frames = 0;
    dec.feed(frame.bytes(), [&](const gm::FrameView& view) {
        ++frames;
        const auto back = gm::decode(view);
        require(back.ok() && gm::same_bits(*back, *msg), "encode/decode round trip differs");
    });
    require(frames == 1 && dec.pending() == 0, "an encoded frame is not exactly one frame");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::span<const std::uint8_t> in(data, size);
    const Seen whole = decode_chunked(
        in, [&](std::size_t) { return size; }, true);
    check_counters(whole, size);

    const Seen bytewise = decode_chunked(
        in, [](std::size_t) { return std::size_t{1}; }, false);
    require_same(whole, bytewise, "byte-by-byte feeding differs from whole");

    const Seen split = decode_chunked(
        in,
        [&](std::size_t pos) {
            const std::size_t a = in[(pos * 7 + 3) % size];
            const std::size_t b = in[(pos * 13 + 5) % size];
            return 1 + (a << 8 | b) % 600;
        },
        false);
    require_same(whole, split, "split feeding differs from whole");

    round_trip(in);
    return 0;
}
