// Test helpers shared by the decoder tests: build frames, feed a decoder in
// different chunkings, and collect what comes out.
#pragma once

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <random>
#include <span>
#include <vector>

#include "gport/protocol/decoder.hpp"
#include "gport/protocol/frame.hpp"

namespace gport::protocol::testing {

using Bytes = std::vector<std::uint8_t>;

inline Bytes bytes_of(const Frame& f) {
    return {f.bytes().begin(), f.bytes().end()};
}

// The wire bytes of a frame built by the library's encoder.
inline Bytes frame_bytes(std::uint8_t command, const Bytes& data) {
    return bytes_of(Frame::make(command, data));
}

inline Bytes cat(std::initializer_list<Bytes> parts) {
    Bytes out;
    for (const auto& p : parts) {
        out.insert(out.end(), p.begin(), p.end());
    }
    return out;
}

enum class Chunking { kWhole, kByteByByte, kRandom };

struct FeedResult {
    std::vector<Bytes> frames;  // every delivered frame, re-encoded to its wire bytes
    DecoderStats stats;
    std::size_t pending = 0;
    std::size_t max_pending = 0;  // largest pending() seen after any feed() call
};

// Feeds `input` to a fresh decoder. kRandom cuts it into chunks of 1..max_chunk
// bytes chosen by a generator seeded with `seed`, so a failure is repeatable.
inline FeedResult run_decoder(std::span<const std::uint8_t> input, Chunking how,
                              std::uint32_t seed = 1, std::size_t max_chunk = 600) {
    Decoder dec;
    FeedResult r;
    auto sink = [&](const FrameView& f) {
        r.frames.push_back(frame_bytes(f.command, {f.data.begin(), f.data.end()}));
    };
    std::mt19937 rng(seed);
    std::uniform_int_distribution<std::size_t> chunk_len(1, max_chunk);
    std::size_t pos = 0;
    while (pos < input.size()) {
        std::size_t n = input.size() - pos;
        if (how == Chunking::kByteByByte) {
            n = 1;
        } else if (how == Chunking::kRandom) {
            n = std::min(n, chunk_len(rng));
        }
        dec.feed(input.subspan(pos, n), sink);
        pos += n;
        r.max_pending = std::max(r.max_pending, dec.pending());
    }
    r.stats = dec.stats();
    r.pending = dec.pending();
    return r;
}

inline std::size_t total_size(const std::vector<Bytes>& frames) {
    std::size_t n = 0;
    for (const auto& f : frames) {
        n += f.size();
    }
    return n;
}

}  // namespace gport::protocol::testing
