// Seeded property test: thousands of random valid frames interleaved with
// noise that is rich in 0xAE, truncated frames, corrupted frames and headers
// that check. Every valid frame must come out, in order, and nothing else.
//
// Why nothing else can come out, by construction:
//   The decoder examines candidates left to right. After accepting a frame it
//   jumps past it; after rejecting one it moves on by one byte. So, as long as
//   no candidate starting inside the noise is a valid frame, it examines every
//   noise byte and then each real frame exactly at its first byte, where it
//   accepts it and jumps past it; bytes inside real frames are never examined.
//   The generator therefore checks, after the whole stream is built, every
//   0xAE that lies in noise: if the bytes from there on (noise, and possibly
//   the following real frames) happen to form a valid frame, that 0xAE is
//   replaced by 0x00. This is done from the end of the stream backwards:
//   changing byte k can only affect candidates that start before k, which
//   are checked afterwards, against the final bytes. Validity is judged with
//   Frame::make (the encoder), not with the decoder under test.
//   The stream ends with kMaxFrameSize bytes of 0x00, so every candidate is
//   decided (none is left waiting for bytes) and the last frame comes out.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "decoder_harness.hpp"

namespace gp = gport::protocol;
using gp::testing::Bytes;
using gp::testing::Chunking;

namespace {

struct Stream {
    Bytes bytes;
    std::vector<bool> is_noise;           // per byte
    std::vector<Bytes> frames;            // the valid frames, in order
    std::size_t noise_before_frames = 0;  // frames preceded by a noise chunk
    std::size_t fixups = 0;               // noise 0xAE bytes neutralised
};

bool valid_frame_at(const Bytes& s, std::size_t k) {
    if (s[k] != gp::kFrameHeader || k + gp::kHeaderSize > s.size() ||
        s[k + 1] != gp::kProtocolVersion) {
        return false;
    }
    const std::size_t len = s[k + 2];
    const std::size_t size = gp::frame_size(len);
    if (k + size > s.size()) {
        return false;
    }
    const auto frame =
        gp::Frame::make(s[k + 3], std::span<const std::uint8_t>(s).subspan(k + 5, len));
    return std::ranges::equal(frame.bytes(), std::span<const std::uint8_t>(s).subspan(k, size));
}

class Generator {
  public:
    explicit Generator(std::uint32_t seed) : rng_(seed) {}

    Stream make(std::size_t frame_count, double noise_chance) {
        Stream st;
        for (std::size_t i = 0; i < frame_count; ++i) {
            if (chance(noise_chance)) {
                append(st, noise(), true);
                ++st.noise_before_frames;
            }
            const Bytes f = random_frame();
            append(st, f, false);
            st.frames.push_back(f);
        }
        append(st, Bytes(gp::kMaxFrameSize, 0x00), true);
        neutralise_accidental_frames(st);
        return st;
    }

  private:
    int uniform(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
    bool chance(double p) { return std::bernoulli_distribution(p)(rng_); }
    std::uint8_t byte() { return static_cast<std::uint8_t>(uniform(0, 255)); }

    Bytes random_frame() {
        Bytes data(static_cast<std::size_t>(uniform(0, 255)));
        for (auto& b : data) {
            b = chance(0.1) ? gp::kFrameHeader : byte();
        }
        return gp::testing::frame_bytes(byte(), data);
    }

    // One noise chunk: one to three pieces of the kinds a bad line produces.
    Bytes noise() {
        Bytes out;
        for (int pieces = uniform(1, 3); pieces > 0; --pieces) {
            const Bytes p = noise_piece();
            out.insert(out.end(), p.begin(), p.end());
        }
        return out;
    }

    Bytes noise_piece() {
        switch (uniform(0, 5)) {
            case 0: {  // random bytes, heavy in 0xAE and the version byte
                Bytes b(static_cast<std::size_t>(uniform(1, 40)));
                for (auto& x : b) {
                    x = chance(0.35) ? 0xAE : chance(0.25) ? 0x01 : byte();
                }
                return b;
            }
            case 1:  // a run of headers
                return Bytes(static_cast<std::size_t>(uniform(1, 8)), 0xAE);
            case 2: {  // a header that checks, then some or all of its claim
                const auto len = static_cast<std::uint8_t>(uniform(1, 255));
                const std::uint8_t cmd = byte();
                Bytes b{0xAE, 0x01, len, cmd, gp::header_sum(0x01, len, cmd)};
                for (int n = uniform(0, len + 4); n > 0; --n) {
                    b.push_back(byte());
                }
                return b;
            }
            case 3: {  // a valid frame cut short
                Bytes f = random_frame();
                f.resize(static_cast<std::size_t>(uniform(1, static_cast<int>(f.size()) - 1)));
                return f;
            }
            case 4: {  // a valid frame with one byte after the 0xAE corrupted
                Bytes f = random_frame();
                const auto at =
                    static_cast<std::size_t>(uniform(1, static_cast<int>(f.size()) - 1));
                f[at] = static_cast<std::uint8_t>(f[at] ^ uniform(1, 255));
                return f;
            }
            default: {  // a zero-length frame with a wrong header sum
                const std::uint8_t cmd = byte();
                const auto sum =
                    static_cast<std::uint8_t>(gp::header_sum(0x01, 0, cmd) + uniform(1, 255));
                return Bytes{0xAE, 0x01, 0x00, cmd, sum};
            }
        }
    }

    static void append(Stream& st, const Bytes& b, bool noise) {
        st.bytes.insert(st.bytes.end(), b.begin(), b.end());
        st.is_noise.insert(st.is_noise.end(), b.size(), noise);
    }

    static void neutralise_accidental_frames(Stream& st) {
        for (std::size_t k = st.bytes.size(); k-- > 0;) {
            if (st.is_noise[k] && valid_frame_at(st.bytes, k)) {
                st.bytes[k] = 0x00;
                ++st.fixups;
            }
        }
    }

    std::mt19937 rng_;
};

struct NoiseFacts {
    std::size_t bytes = 0;
    std::size_t headers = 0;  // 0xAE bytes in noise: each is one rejected candidate
};

NoiseFacts noise_facts(const Stream& st) {
    NoiseFacts f;
    for (std::size_t i = 0; i < st.bytes.size(); ++i) {
        if (st.is_noise[i]) {
            ++f.bytes;
            f.headers += st.bytes[i] == gp::kFrameHeader ? 1 : 0;
        }
    }
    return f;
}

void expect_exact(const Stream& st, const gp::testing::FeedResult& r, const std::string& how) {
    SCOPED_TRACE(how);
    const NoiseFacts noise = noise_facts(st);
    ASSERT_EQ(r.frames.size(), st.frames.size());
    for (std::size_t i = 0; i < st.frames.size(); ++i) {
        ASSERT_EQ(r.frames[i], st.frames[i]) << "frame " << i;
    }
    EXPECT_EQ(r.stats.bytes, st.bytes.size());
    EXPECT_EQ(r.stats.frames, st.frames.size());
    EXPECT_EQ(r.stats.garbage_bytes, noise.bytes);
    EXPECT_EQ(r.stats.header_errors + r.stats.crc_errors, noise.headers);
    EXPECT_EQ(r.stats.resyncs, st.noise_before_frames);
    EXPECT_EQ(r.pending, 0U);
    EXPECT_LE(r.max_pending, gp::kMaxFrameSize - 1);
}

void check_all_chunkings(const Stream& st) {
    expect_exact(st, gp::testing::run_decoder(st.bytes, Chunking::kWhole), "whole");
    expect_exact(st, gp::testing::run_decoder(st.bytes, Chunking::kByteByByte), "byte by byte");
    for (std::uint32_t seed : {7U, 8U, 9U}) {
        for (std::size_t max_chunk :
             {std::size_t{3}, std::size_t{64}, std::size_t{300}, std::size_t{4096}}) {
            expect_exact(st, gp::testing::run_decoder(st.bytes, Chunking::kRandom, seed, max_chunk),
                         "random splits up to " + std::to_string(max_chunk) + ", seed " +
                             std::to_string(seed));
        }
    }
}

}  // namespace

TEST(DecoderProperty, EveryFrameThroughNoiseRichInHeaders) {
    for (std::uint32_t seed : {1U, 2U, 3U}) {
        SCOPED_TRACE("generator seed " + std::to_string(seed));
        const Stream st = Generator(seed).make(3000, 0.6);
        // The noise really is hostile: many candidates, few accidental frames.
        const NoiseFacts noise = noise_facts(st);
        EXPECT_GT(noise.headers, 3000U);
        EXPECT_LT(st.fixups, 100U);
        check_all_chunkings(st);
    }
}

TEST(DecoderProperty, CleanStreamOfRandomFrames) {
    const Stream st = Generator(42).make(3000, 0.0);
    EXPECT_EQ(noise_facts(st).headers, 0U);
    check_all_chunkings(st);
}
