// The acceptance rules of a signed link, each with the attack it stops:
// unsigned and wrongly signed frames, replays, old timestamps, a moved link
// id, a truncated signature, and a flood of streams.
#include "gport/mavlink/verifier.hpp"

#include <gtest/gtest.h>

#include "gport/mavlink/messages.hpp"
#include "samples.hpp"
#include "signing_samples.hpp"

namespace gport::mavlink {
namespace {

using testing::from_hex;
using Bytes = std::vector<std::uint8_t>;

constexpr std::uint64_t kNow = 40'000'000'000'000;  // some time in 2027

SecretKey key() {
    return *parse_key_hex(testing::kNodeKeyHex);
}

Bytes signed_frame(std::uint8_t sysid, std::uint8_t compid, std::uint8_t link,
                   std::uint64_t timestamp, std::uint8_t seq = 0) {
    Frame f = encode(testing::sample_set_attitude(), {seq, sysid, compid}, true);
    sign(f, key(), link, timestamp);
    return {f.bytes().begin(), f.bytes().end()};
}

TEST(Verifier, ACorrectlySignedFrameIsAccepted) {
    Verifier v(key());
    const Verdict verdict = v.check(signed_frame(1, 1, 0, kNow), kNow);
    EXPECT_EQ(verdict.check, SignatureCheck::kAccepted);
    EXPECT_EQ(verdict.timestamp, kNow);
    EXPECT_EQ(v.streams(), 1U);
}

TEST(Verifier, NodeMavlinksFrameIsAcceptedNearItsTime) {
    Verifier v(key());
    EXPECT_EQ(v.check(from_hex(testing::kNodeHeartbeatHex), testing::kNodeHeartbeatTimestamp).check,
              SignatureCheck::kAccepted);
}

TEST(Verifier, AnUnsignedFrameIsRefused) {
    Verifier v(key());
    const Frame plain = encode(testing::sample_set_attitude(), {0, 1, 1});
    EXPECT_EQ(v.check(plain.bytes(), kNow).check, SignatureCheck::kUnsigned);
    EXPECT_EQ(v.streams(), 0U);
}

TEST(Verifier, AnAllZeroOrForeignSignatureIsRefusedAndChangesNothing) {
    Verifier v(key());
    Frame zero = encode(testing::sample_set_attitude(), {0, 99, 1}, true);  // block left zero
    EXPECT_EQ(v.check(zero.bytes(), kNow).check, SignatureCheck::kBadSignature);
    std::array<std::uint8_t, 32> other_bytes{};
    other_bytes.fill(0x5a);
    Frame foreign = encode(testing::sample_set_attitude(), {0, 1, 1}, true);
    sign(foreign, SecretKey(other_bytes), 0, kNow + 10);
    EXPECT_EQ(v.check(foreign.bytes(), kNow).check, SignatureCheck::kBadSignature);
    EXPECT_EQ(v.streams(), 0U);
    // The wrongly signed frame's far-future timestamp did not poison the stream.
    EXPECT_EQ(v.check(signed_frame(1, 1, 0, kNow + 1), kNow).check, SignatureCheck::kAccepted);
}

TEST(Verifier, ReplayingAFrameOrItsTimestampIsRefused) {
    Verifier v(key());
    const Bytes first = signed_frame(1, 1, 0, kNow + 5);
    ASSERT_EQ(v.check(first, kNow).check, SignatureCheck::kAccepted);
    EXPECT_EQ(v.check(first, kNow).check, SignatureCheck::kReplayed);  // the same frame again
    EXPECT_EQ(v.check(signed_frame(1, 1, 0, kNow + 5, 1), kNow).check,
              SignatureCheck::kReplayed);  // another frame, equal timestamp
    EXPECT_EQ(v.check(signed_frame(1, 1, 0, kNow + 4, 2), kNow).check,
              SignatureCheck::kReplayed);  // older
    EXPECT_EQ(v.check(signed_frame(1, 1, 0, kNow + 6, 3), kNow).check, SignatureCheck::kAccepted);
}

TEST(Verifier, StreamsAreTheirOwnSystemComponentAndLink) {
    Verifier v(key());
    ASSERT_EQ(v.check(signed_frame(1, 1, 0, kNow + 100), kNow).check, SignatureCheck::kAccepted);
    // Other streams may be behind stream (1,1,0), within a minute of ours.
    EXPECT_EQ(v.check(signed_frame(1, 1, 1, kNow + 50), kNow).check, SignatureCheck::kAccepted);
    EXPECT_EQ(v.check(signed_frame(1, 2, 0, kNow + 50), kNow).check, SignatureCheck::kAccepted);
    EXPECT_EQ(v.check(signed_frame(255, 190, 0, kNow + 50), kNow).check, SignatureCheck::kAccepted);
    EXPECT_EQ(v.streams(), 4U);
}

TEST(Verifier, MovingACapturedFrameToAnotherLinkIdBreaksItsSignature) {
    Verifier v(key());
    const Bytes captured = signed_frame(1, 1, 0, kNow + 5);
    ASSERT_EQ(v.check(captured, kNow).check, SignatureCheck::kAccepted);
    Bytes moved = captured;
    moved[moved.size() - kSignatureSize] = 7;  // the link id byte: a fresh stream, if it verified
    EXPECT_EQ(v.check(moved, kNow).check, SignatureCheck::kBadSignature);
    Bytes newer = captured;
    newer[moved.size() - kSignatureSize + 1] ^= 0x01;  // the timestamp, bumped by hand
    EXPECT_EQ(v.check(newer, kNow).check, SignatureCheck::kBadSignature);
}

TEST(Verifier, ATruncatedSignatureIsRefused) {
    Verifier v(key());
    const Bytes whole = signed_frame(1, 1, 0, kNow);
    for (std::size_t cut = 1; cut <= kSignatureSize; ++cut) {
        const Bytes shorter(whole.begin(), whole.end() - static_cast<std::ptrdiff_t>(cut));
        EXPECT_EQ(v.check(shorter, kNow).check, SignatureCheck::kBadSignature) << cut;
    }
    EXPECT_EQ(v.check(Bytes{0xFD, 0x01}, kNow).check, SignatureCheck::kUnsigned);
    EXPECT_EQ(v.streams(), 0U);
}

TEST(Verifier, ANewStreamMoreThanAMinuteBehindIsRefused) {
    Verifier v(key());
    EXPECT_EQ(v.check(signed_frame(1, 1, 0, kNow - kOneMinute - 1), kNow).check,
              SignatureCheck::kTooOld);
    EXPECT_EQ(v.streams(), 0U);
    EXPECT_EQ(v.check(signed_frame(1, 1, 0, kNow - kOneMinute), kNow).check,
              SignatureCheck::kAccepted);
    // A known stream is judged by its own last timestamp only (as MAVLink's
    // C library does): frames after it are taken even if the local clock ran on.
    EXPECT_EQ(v.check(signed_frame(1, 1, 0, kNow - kOneMinute + 1), kNow + kOneMinute).check,
              SignatureCheck::kAccepted);
}

TEST(Verifier, AFullTableRefusesNewStreamsUnlessOneIsStale) {
    Verifier v(key(), 4);
    for (std::uint8_t c = 1; c <= 4; ++c) {
        ASSERT_EQ(v.check(signed_frame(1, c, 0, kNow), kNow).check, SignatureCheck::kAccepted);
    }
    EXPECT_EQ(v.check(signed_frame(1, 5, 0, kNow), kNow).check, SignatureCheck::kStreamsFull);
    EXPECT_EQ(v.streams(), 4U);
    // Known streams go on.
    EXPECT_EQ(v.check(signed_frame(1, 2, 0, kNow + 1), kNow).check, SignatureCheck::kAccepted);
    // Two minutes later streams 1, 3 and 4 are stale: a new one replaces one of them...
    const std::uint64_t later = kNow + 2 * kOneMinute;
    EXPECT_EQ(v.check(signed_frame(1, 5, 0, later), later).check, SignatureCheck::kAccepted);
    EXPECT_EQ(v.streams(), 4U);
    // ... and a replay of a forgotten stream is still refused, as too old.
    EXPECT_EQ(v.check(signed_frame(1, 1, 0, kNow + 10), later).check, SignatureCheck::kTooOld);
}

TEST(Verifier, ChecksHaveNames) {
    EXPECT_EQ(to_string(SignatureCheck::kUnsigned), "unsigned");
    EXPECT_EQ(to_string(SignatureCheck::kBadSignature), "bad signature");
    EXPECT_EQ(to_string(SignatureCheck::kReplayed), "replayed");
    EXPECT_EQ(to_string(SignatureCheck::kTooOld), "too old");
    EXPECT_EQ(to_string(SignatureCheck::kStreamsFull), "stream table full");
}

}  // namespace
}  // namespace gport::mavlink
