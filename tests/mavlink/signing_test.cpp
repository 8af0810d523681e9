// MAVLink 2 signing: the key, the timestamps, signing and reading the
// block, checked against frames node-mavlink signed (signing_samples.hpp).
#include "gport/mavlink/signing.hpp"

#include <gtest/gtest.h>

#include <chrono>

#include "gport/mavlink/decoder.hpp"
#include "gport/mavlink/messages.hpp"
#include "samples.hpp"
#include "signing_samples.hpp"

namespace gport::mavlink {
namespace {

using testing::from_hex;

SecretKey node_key() {
    return *parse_key_hex(testing::kNodeKeyHex);
}

TEST(SigningKey, SixtyFourHexDigitsEitherCase) {
    const auto lower = parse_key_hex(testing::kNodeKeyHex);
    ASSERT_TRUE(lower) << lower.error().message;
    EXPECT_EQ(lower->bytes()[0], 0x6b);
    EXPECT_EQ(lower->bytes()[31], 0xb2);
    std::string upper(testing::kNodeKeyHex);
    for (auto& c : upper) {
        c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    }
    const auto parsed = parse_key_hex(upper);
    ASSERT_TRUE(parsed);
    EXPECT_TRUE(std::ranges::equal(parsed->bytes(), lower->bytes()));
}

TEST(SigningKey, WrongLengthAndBadDigitsAreRefusedWithoutEchoingTheKey) {
    const auto short_key = parse_key_hex(testing::kNodeKeyHex.substr(0, 62));
    ASSERT_FALSE(short_key);
    EXPECT_NE(short_key.error().message.find("62 characters"), std::string::npos);
    EXPECT_NE(short_key.error().message.find("exactly 64 hexadecimal digits"), std::string::npos);
    EXPECT_FALSE(parse_key_hex(std::string(testing::kNodeKeyHex) + "00"));
    EXPECT_FALSE(parse_key_hex(""));
    std::string bad(testing::kNodeKeyHex);
    bad[10] = 'g';
    const auto refused = parse_key_hex(bad);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("character 11"), std::string::npos);
    EXPECT_EQ(refused.error().message.find(testing::kNodeKeyHex.substr(0, 8)), std::string::npos);
    EXPECT_FALSE(parse_key_hex(" " + std::string(testing::kNodeKeyHex.substr(1))));  // caller trims
}

TEST(SigningTimestamp, TenMicrosecondsSince2015) {
    using namespace std::chrono;
    const system_clock::time_point epoch{seconds(kSigningEpochUnixSeconds)};
    EXPECT_EQ(signing_timestamp(epoch), 0U);
    EXPECT_EQ(signing_timestamp(epoch + seconds(1)), kTimestampsPerSecond);
    EXPECT_EQ(signing_timestamp(epoch + microseconds(25)), 2U);
    EXPECT_EQ(signing_timestamp(epoch - seconds(1)), 0U);  // a clock before 2015
    // node-mavlink's timestamp of 2025-01-01T00:00:00.123Z
    const auto t = epoch + days(3653) + milliseconds(123);
    EXPECT_EQ(signing_timestamp(t), testing::kNodeHeartbeatTimestamp);
}

// Issue 30: one frame stamped 23 h ahead from a key holder (or a ground
// station whose clock is hours ahead) pulls ours at most 30 s ahead of our
// clock, and the reference for incoming new streams stays within 30 s of
// it: a vehicle whose clock is right is never "too old".
TEST(SendClock, AFrameHoursAheadPullsOursAtMost30SecondsAhead) {
    const std::uint64_t now = 37'000'000'000'000ULL;  // 2026
    const std::uint64_t hours23 = 23ULL * 3600 * kTimestampsPerSecond;
    SendClock clock(0, now);
    const auto observed = clock.observe(now + hours23, now);
    EXPECT_TRUE(observed.capped);
    EXPECT_EQ(observed.raised, SendClock::kMaxLead);
    EXPECT_EQ(clock.current(), now + SendClock::kMaxLead);
    EXPECT_EQ(clock.reference(now), now + SendClock::kMaxLead);
    // Repeated, a second later: ours follows the wall clock, no further.
    EXPECT_TRUE(clock.observe(now + hours23, now + kTimestampsPerSecond).capped);
    EXPECT_EQ(clock.current(), now + kTimestampsPerSecond + SendClock::kMaxLead);
    EXPECT_EQ(clock.next(now), now + kTimestampsPerSecond + SendClock::kMaxLead + 1);
    // 2^48 - 1: no saturation.
    EXPECT_TRUE(clock.observe(kMaxTimestamp, now).capped);
    EXPECT_FALSE(clock.saturated());
}

TEST(SendClock, TheIncomingReferenceStaysWithin30SecondsOfTheClock) {
    const std::uint64_t now = 37'000'000'000'000ULL;
    SendClock far(/*floor=*/now + 3600 * kTimestampsPerSecond, now);  // a floor an hour ahead
    EXPECT_EQ(far.reference(now), now + SendClock::kMaxLead);
    SendClock behind(/*floor=*/1000, now);
    EXPECT_EQ(behind.reference(now + 5), now + 5);  // never behind the wall clock
    SendClock late(0, kMaxTimestamp - 5);
    EXPECT_EQ(late.reference(kMaxTimestamp - 5), kMaxTimestamp - 5);
}

// A stored value is trusted up to 30 s ahead of the clock: a planted
// 2^48 - 1, or a day ahead from an older version, is not.
TEST(SendClock, AStoredValueFarAheadIsNotTrusted) {
    const std::uint64_t now = 37'000'000'000'000ULL;
    EXPECT_EQ(trusted_floor(kMaxTimestamp, now), now + SendClock::kMaxLead);
    EXPECT_EQ(trusted_floor(now + 23ULL * 3600 * kTimestampsPerSecond, now),
              now + SendClock::kMaxLead);
    EXPECT_EQ(trusted_floor(now + SendClock::kMaxLead, now), now + SendClock::kMaxLead);
    EXPECT_EQ(trusted_floor(now + 1000, now), now + 1000);  // a crash's reservation
    EXPECT_EQ(trusted_floor(5, now), 5U);  // behind the clock: the clock wins in SendClock
    EXPECT_EQ(trusted_floor(kMaxTimestamp, kMaxTimestamp - 1), kMaxTimestamp);
}

TEST(SendClock, NeverBackwardsFollowsTheClockAndAcceptedTimestamps) {
    SendClock clock(/*floor=*/1000, /*now=*/10);  // a clock behind the stored value
    EXPECT_EQ(clock.next(10), 1001U);
    EXPECT_EQ(clock.next(10), 1002U);  // +1 per frame while the clock is behind
    EXPECT_EQ(clock.next(5000), 5000U);
    EXPECT_EQ(clock.next(4000), 5001U);  // the clock stepped back: still forward
    // A correctly signed frame from a peer a little ahead of us (within 30 s).
    const auto observed = clock.observe(9000, 5001);
    EXPECT_FALSE(observed.capped);
    EXPECT_EQ(observed.raised, 9000U - 5001U);
    EXPECT_EQ(clock.next(5002), 9001U);
    EXPECT_EQ(clock.observe(10, 5002).raised, 0U);  // older: ignored
    EXPECT_EQ(clock.current(), 9001U);
    SendClock fresh(/*floor=*/0, /*now=*/777);
    EXPECT_EQ(fresh.next(777), 778U);
    SendClock saturated(kMaxTimestamp, 0);
    EXPECT_TRUE(saturated.saturated());
    EXPECT_EQ(saturated.next(0), kMaxTimestamp);
    // Our own clock near the end of the range: no overflow, the cap is 2^48 - 1.
    SendClock late(0, kMaxTimestamp - 5);
    EXPECT_FALSE(late.observe(kMaxTimestamp, kMaxTimestamp - 5).capped);
    EXPECT_TRUE(late.saturated());
}

TEST(Signing, NodeMavlinksSignedFramesVerifyAndOursEqualThem) {
    const auto wire = from_hex(testing::kNodeHeartbeatHex);
    ASSERT_TRUE(signature_matches(node_key(), wire));
    const auto block = signature_block_of(wire);
    ASSERT_TRUE(block);
    EXPECT_EQ(block->link_id, testing::kNodeHeartbeatLink);
    EXPECT_EQ(block->timestamp, testing::kNodeHeartbeatTimestamp);

    // The same heartbeat, encoded and signed by us: byte for byte the same.
    Heartbeat hb;
    hb.type = 2;
    hb.autopilot = 3;
    hb.base_mode = 81;
    hb.custom_mode = 4;
    hb.system_status = 4;
    hb.mavlink_version = 3;
    Frame frame = encode(hb, {7, 1, 1}, /*signed_frame=*/true);
    sign(frame, node_key(), testing::kNodeHeartbeatLink, testing::kNodeHeartbeatTimestamp);
    EXPECT_TRUE(std::ranges::equal(frame.bytes(), wire));

    EXPECT_TRUE(signature_matches(node_key(), from_hex(testing::kNodeSetAttitudeHex)));
}

TEST(Signing, TheDecoderDeliversTheWholeSignedFrame) {
    const auto wire = from_hex(testing::kNodeSetAttitudeHex);
    Decoder decoder;
    int frames = 0;
    decoder.feed(wire, [&](const FrameView& view) {
        ++frames;
        EXPECT_TRUE(view.is_signed);
        EXPECT_TRUE(std::ranges::equal(view.bytes, wire));
        EXPECT_TRUE(signature_matches(node_key(), view.bytes));
    });
    EXPECT_EQ(frames, 1);
}

TEST(Signing, AnyChangedBitOrAnotherKeyFails) {
    const auto wire = from_hex(testing::kNodeSetAttitudeHex);
    for (std::size_t i = 0; i < wire.size(); ++i) {
        auto altered = wire;
        altered[i] ^= 0x10;
        EXPECT_FALSE(signature_matches(node_key(), altered)) << "byte " << i;
    }
    std::array<std::uint8_t, 32> other{};
    other[0] = 1;
    EXPECT_FALSE(signature_matches(SecretKey(other), wire));
}

TEST(Signing, TruncatedOrUnsignedFramesHaveNoSignature) {
    const auto wire = from_hex(testing::kNodeHeartbeatHex);
    for (std::size_t cut = 1; cut <= kSignatureSize; ++cut) {
        const std::vector<std::uint8_t> shorter(wire.begin(),
                                                wire.end() - static_cast<std::ptrdiff_t>(cut));
        EXPECT_FALSE(signature_block_of(shorter)) << cut;
        EXPECT_FALSE(signature_matches(node_key(), shorter)) << cut;
    }
    auto longer = wire;
    longer.push_back(0);
    EXPECT_FALSE(signature_block_of(longer));
    const Frame plain = encode(testing::sample_heartbeat(), {0, 1, 154});
    EXPECT_FALSE(signature_block_of(plain.bytes()));
    EXPECT_FALSE(signature_matches(node_key(), plain.bytes()));
}

TEST(Signing, SigningAnUnsignedFrameOrAnOversizedTimestampIsAProgrammingError) {
    Frame plain = encode(testing::sample_heartbeat(), {0, 1, 154});
    EXPECT_THROW(sign(plain, node_key(), 0, 1), std::invalid_argument);
    Frame flagged = encode(testing::sample_heartbeat(), {0, 1, 154}, true);
    EXPECT_THROW(sign(flagged, node_key(), 0, kMaxTimestamp + 1), std::invalid_argument);
}

TEST(Signing, ASignedFrameCarriesTheFlagInsideItsChecksum) {
    const Frame plain = encode(testing::sample_heartbeat(), {0, 1, 154});
    Frame flagged = encode(testing::sample_heartbeat(), {0, 1, 154}, true);
    EXPECT_EQ(flagged.size(), plain.size() + kSignatureSize);
    EXPECT_EQ(flagged.bytes()[2], kIncompatSigned);
    EXPECT_NE(flagged.bytes()[flagged.size() - kSignatureSize - 1], plain.bytes().back());
    sign(flagged, node_key(), 9, 123456);
    Decoder decoder;
    int frames = 0;
    decoder.feed(flagged.bytes(), [&](const FrameView& view) {
        ++frames;
        EXPECT_TRUE(view.is_signed);
        EXPECT_EQ(signature_block_of(view.bytes)->timestamp, 123456U);
        EXPECT_EQ(signature_block_of(view.bytes)->link_id, 9);
    });
    EXPECT_EQ(frames, 1);
}

}  // namespace
}  // namespace gport::mavlink
