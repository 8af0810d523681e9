// Table-driven decoder cases: name, input bytes, the frames that must come out
// and the counters that must result. Every case is fed whole, one byte at a
// time and in seeded random splits, and must give the same result each way.
#include <gtest/gtest.h>

#include <algorithm>
#include <ostream>
#include <string>
#include <vector>

#include "decoder_harness.hpp"

namespace gp = gport::protocol;
using gp::testing::Bytes;
using gp::testing::cat;
using gp::testing::Chunking;

namespace {

// The seed's 0x87 example (21 bytes; no 0xAE after its first byte).
const Bytes kAttitude{0xAE, 0x01, 0x0C, 0x87, 0x94, 0x00, 0x00, 0x00, 0x00, 0xA7, 0xF0,
                      0x7F, 0xF8, 0xF0, 0xFF, 0xD2, 0x01, 0x44, 0x0D, 0xAD, 0x53};
const Bytes kGetSettings{0xAE, 0x01, 0x00, 0x13, 0x14};  // zero-length frame
const Bytes kAck{0xAE, 0x01, 0x00, 0x16, 0x17};          // zero-length frame
const Bytes kCamera{0xAE, 0x01, 0x01, 0x86, 0x88, 0x01, 0xCC, 0xC0, 0xC5, 0xC3};

// A 255-byte frame whose data is all 0xAE 0x01 pairs: headers inside a frame
// that was accepted must never be looked at.
Bytes big_frame() {
    Bytes data(255);
    for (std::size_t i = 0; i < data.size(); ++i) {
        data[i] = i % 2 == 0 ? 0xAE : 0x01;
    }
    return gp::testing::frame_bytes(0x42, data);
}

Bytes first(const Bytes& b, std::size_t n) {
    return {b.begin(), b.begin() + static_cast<std::ptrdiff_t>(n)};
}

Bytes with_byte(Bytes b, std::size_t index, std::uint8_t value) {
    b.at(index) = value;
    return b;
}

struct Expected {
    std::uint64_t garbage = 0;
    std::uint64_t header_errors = 0;
    std::uint64_t crc_errors = 0;
    std::uint64_t resyncs = 0;
    std::size_t pending = 0;
};

struct Case {
    std::string name;
    Bytes input;
    std::vector<Bytes> frames;
    Expected stats;
};

// A false header claiming 255 data bytes: AE 01 FF 10, sum (01+FF+10)&FF = 10.
const Bytes kLongClaim{0xAE, 0x01, 0xFF, 0x10, 0x10};
// A header that checks (sum 01+02+50 = 53) with two data bytes and a wrong CRC.
const Bytes kBadCrcCandidate{0xAE, 0x01, 0x02, 0x50, 0x53, 0x11, 0x22, 0x00, 0x00, 0x00, 0x00};

std::vector<Case> cases() {
    const Bytes big = big_frame();
    const Bytes no_header(250, 0x00);
    const Bytes overlap_b0 = gp::testing::frame_bytes(0x33, Bytes(0xB0, 0x5C));
    return {
        {"Empty", {}, {}, {}},
        {"SingleFrame", kAttitude, {kAttitude}, {}},
        {"GarbageBefore", cat({{0x00, 0x11, 0x22}, kAttitude}), {kAttitude}, {3, 0, 0, 1, 0}},
        {"GarbageBetween",
         cat({kAttitude, {0x55, 0x66}, kGetSettings}),
         {kAttitude, kGetSettings},
         {2, 0, 0, 1, 0}},
        {"GarbageAfter", cat({kAttitude, {0x01, 0x02}}), {kAttitude}, {2, 0, 0, 0, 0}},
        // The claim of 259 bytes after the header swallows the real frame; once
        // enough bytes arrived the CRC disproves it and the frame comes out.
        {"FalseHeaderSwallowsRealFrame",
         cat({kLongClaim, kAttitude, no_header}),
         {kAttitude},
         {5 + 250, 0, 1, 1, 0}},
        // A candidate whose own header overlaps a real frame's header: AE 01
        // then a frame of 0xB0 data bytes reads as AE 01 AE 01 B0, a header
        // that checks (01+AE+01 = B0). Its CRC fails; the frame two bytes on
        // must still come out, so the re-scan may skip one byte only.
        {"FalseHeaderOverlapsRealHeader",
         cat({{0xAE, 0x01}, overlap_b0}),
         {overlap_b0},
         {2, 0, 1, 1, 0}},
        // Same at the third byte: AE 01 52 AE 01 checks (01+52+AE = 01).
        {"FalseHeaderOverlapsRealHeaderLater",
         cat({{0xAE, 0x01, 0x52}, kAttitude, no_header}),
         {kAttitude},
         {3 + 250, 0, 1, 1, 0}},
        // Until the claim is disproved the real frame is held back, not lost.
        {"FalseHeaderClaimNotYetDisproved", cat({kLongClaim, kAttitude}), {}, {0, 0, 0, 0, 26}},
        {"WrongVersion",
         cat({{0xAE, 0x02, 0x00, 0x13, 0x15}, kGetSettings}),
         {kGetSettings},
         {5, 1, 0, 1, 0}},
        {"VersionZeroThenFrame", cat({{0xAE, 0x00}, kAck}), {kAck}, {2, 1, 0, 1, 0}},
        // Cut after 10 bytes: the next frame fills the claimed length, the CRC
        // fails, and the re-scan from the second byte finds the next frame.
        {"TruncatedFrameThenFrame",
         cat({first(kAttitude, 10), kAttitude}),
         {kAttitude},
         {10, 0, 1, 1, 0}},
        // Cut inside the header: the header sum takes the next frame's bytes.
        {"TruncatedHeaderThenFrame",
         cat({first(kAttitude, 3), kGetSettings}),
         {kGetSettings},
         {3, 1, 0, 1, 0}},
        // The cut frame's own data is AE 01 pairs: after its CRC fails, each
        // of its 98 inner 0xAE bytes is a candidate with a bad header sum.
        {"TruncatedBigFrameThenFrames",
         cat({first(big, 200), kAttitude, big, kCamera}),
         {kAttitude, big, kCamera},
         {200, 98, 1, 1, 0}},
        {"BadHeaderSum",
         cat({with_byte(kAttitude, 4, 0x95), kGetSettings}),
         {kGetSettings},
         {21, 1, 0, 1, 0}},
        {"BadCrcByte",
         cat({with_byte(kAttitude, 20, 0x54), kGetSettings}),
         {kGetSettings},
         {21, 0, 1, 1, 0}},
        {"BadDataByte", cat({with_byte(kAttitude, 9, 0xA8), kCamera}), {kCamera}, {21, 0, 1, 1, 0}},
        {"HeaderChecksButCrcWrong",
         cat({kBadCrcCandidate, kAttitude}),
         {kAttitude},
         {11, 0, 1, 1, 0}},
        {"ZeroLengthFrames",
         cat({kGetSettings, kAck, kGetSettings}),
         {kGetSettings, kAck, kGetSettings},
         {}},
        {"MaxLengthFrame", big, {big}, {}},
        {"MaxLengthFramesWithGarbage",
         cat({{0x07}, big, {0x08, 0x09}, big}),
         {big, big},
         {3, 0, 0, 2, 0}},
        {"BackToBack",
         cat({kAttitude, kAttitude, kCamera, kGetSettings, big, kAck, kAttitude}),
         {kAttitude, kAttitude, kCamera, kGetSettings, big, kAck, kAttitude},
         {}},
        // Each 0xAE is followed by 0xAE, not the version: three header errors.
        {"HeaderRunBeforeFrame",
         cat({{0xAE, 0xAE, 0xAE}, kAttitude}),
         {kAttitude},
         {3, 3, 0, 1, 0}},
        {"HeaderRunBetweenFrames",
         cat({kCamera, {0xAE, 0xAE, 0xAE, 0xAE}, kAck}),
         {kCamera, kAck},
         {4, 4, 0, 1, 0}},
        // The last 0xAE may still start a frame: it is pending, not garbage.
        {"HeaderRunAtEnd", cat({kAttitude, {0xAE, 0xAE, 0xAE}}), {kAttitude}, {2, 2, 0, 0, 1}},
        {"PartialHeaderAtEnd", cat({kAttitude, {0xAE, 0x01, 0x0C}}), {kAttitude}, {0, 0, 0, 0, 3}},
        {"PartialFrameAtEnd", cat({kAttitude, first(big, 263)}), {kAttitude}, {0, 0, 0, 0, 263}},
    };
}

// gtest prints a failing parameter; the name says more than its bytes.
void PrintTo(const Case& c, std::ostream* os) {
    *os << c.name;
}

class DecoderCase : public ::testing::TestWithParam<Case> {};

void expect_result(const Case& c, const gp::testing::FeedResult& r, const std::string& how) {
    SCOPED_TRACE(c.name + " fed " + how);
    EXPECT_EQ(r.frames, c.frames);
    EXPECT_EQ(r.stats.bytes, c.input.size());
    EXPECT_EQ(r.stats.frames, c.frames.size());
    EXPECT_EQ(r.stats.garbage_bytes, c.stats.garbage);
    EXPECT_EQ(r.stats.header_errors, c.stats.header_errors);
    EXPECT_EQ(r.stats.crc_errors, c.stats.crc_errors);
    EXPECT_EQ(r.stats.resyncs, c.stats.resyncs);
    EXPECT_EQ(r.pending, c.stats.pending);
    // Every byte fed is garbage, part of a delivered frame, or still pending.
    EXPECT_EQ(r.stats.garbage_bytes + gp::testing::total_size(r.frames) + r.pending, r.stats.bytes);
    EXPECT_LE(r.max_pending, gp::kMaxFrameSize - 1);
}

TEST_P(DecoderCase, FedWhole) {
    const Case& c = GetParam();
    expect_result(c, gp::testing::run_decoder(c.input, Chunking::kWhole), "whole");
}

TEST_P(DecoderCase, FedByteByByte) {
    const Case& c = GetParam();
    expect_result(c, gp::testing::run_decoder(c.input, Chunking::kByteByByte), "byte by byte");
}

TEST_P(DecoderCase, FedInRandomSplits) {
    const Case& c = GetParam();
    for (std::uint32_t seed = 1; seed <= 50; ++seed) {
        const std::size_t max_chunk = seed % 2 == 0 ? 8 : 300;
        expect_result(c, gp::testing::run_decoder(c.input, Chunking::kRandom, seed, max_chunk),
                      "in random splits, seed " + std::to_string(seed));
    }
}

INSTANTIATE_TEST_SUITE_P(Table, DecoderCase, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<Case>& param_info) {
                             return param_info.param.name;
                         });

TEST(Decoder, ResetForgetsThePartialFrameAndCountsItAsGarbage) {
    gp::Decoder dec;
    std::vector<Bytes> out;
    auto sink = [&](const gp::FrameView& f) {
        out.push_back(gp::testing::frame_bytes(f.command, {f.data.begin(), f.data.end()}));
    };
    dec.feed(first(kAttitude, 12), sink);
    EXPECT_EQ(dec.pending(), 12U);
    dec.reset();
    EXPECT_EQ(dec.pending(), 0U);
    EXPECT_EQ(dec.stats().garbage_bytes, 12U);
    // The rest of the cut frame is garbage now; the next frame is a resync.
    dec.feed(cat({Bytes(kAttitude.begin() + 12, kAttitude.end()), kCamera}), sink);
    EXPECT_EQ(out, std::vector<Bytes>{kCamera});
    EXPECT_EQ(dec.stats().garbage_bytes, 21U);
    EXPECT_EQ(dec.stats().resyncs, 1U);
    EXPECT_EQ(dec.stats().frames, 1U);
}

TEST(Decoder, FrameViewCarriesCommandAndData) {
    gp::Decoder dec;
    int calls = 0;
    dec.feed(kCamera, [&](const gp::FrameView& f) {
        ++calls;
        EXPECT_EQ(f.command, 0x86);
        ASSERT_EQ(f.data.size(), 1U);
        EXPECT_EQ(f.data[0], 0x01);
    });
    EXPECT_EQ(calls, 1);
}

}  // namespace
