// Fault injection, deterministic: how frames become writes, and when the
// link falls silent or vanishes.
#include "gport/sim/faults.hpp"

#include <gtest/gtest.h>

#include "gport/protocol/decoder.hpp"

namespace gport::sim {
namespace {

namespace p = gport::protocol;
using namespace std::chrono_literals;

std::vector<p::Frame> attitude_frames(std::size_t n) {
    std::vector<p::Frame> frames;
    for (std::size_t i = 0; i < n; ++i) {
        p::Attitude a;
        a.hall.yaw = static_cast<std::int16_t>(i);
        frames.push_back(p::encode(a));
    }
    return frames;
}

p::DecoderStats decode(const std::vector<Chunk>& chunks, std::size_t* frames = nullptr) {
    p::Decoder d;
    std::size_t n = 0;
    for (const auto& c : chunks) {
        d.feed(c, [&](const p::FrameView&) { ++n; });
    }
    if (frames != nullptr) {
        *frames = n;
    }
    return d.stats();
}

TEST(FaultInjector, WithoutFaultsEachFrameIsOneWrite) {
    FaultInjector f({});
    const auto chunks = f.shape(attitude_frames(3), 20ms);
    ASSERT_EQ(chunks.size(), 3U);
    EXPECT_EQ(chunks[0].size(), p::frame_size(12));
}

TEST(FaultInjector, SplitWritesEveryByteAlone) {
    FaultOptions o;
    o.shape = WriteShape::kSplit;
    FaultInjector f(o);
    const auto chunks = f.shape(attitude_frames(2), 20ms);
    EXPECT_EQ(chunks.size(), 2 * p::frame_size(12));
    for (const auto& c : chunks) {
        EXPECT_EQ(c.size(), 1U);
    }
    std::size_t frames = 0;
    decode(chunks, &frames);
    EXPECT_EQ(frames, 2U);
}

TEST(FaultInjector, MergeGroupsFramesAndFlushesAPartialGroupInTime) {
    FaultOptions o;
    o.shape = WriteShape::kMerge;
    o.merge_count = 3;
    FaultInjector f(o);
    auto chunks = f.shape(attitude_frames(4), 20ms);
    ASSERT_EQ(chunks.size(), 1U);
    EXPECT_EQ(chunks[0].size(), 3 * p::frame_size(12));
    EXPECT_EQ(f.next_flush(), 20ms + o.merge_max_wait);
    EXPECT_TRUE(f.shape({}, 50ms).empty());
    chunks = f.shape({}, 120ms);  // the fourth frame waited long enough
    ASSERT_EQ(chunks.size(), 1U);
    EXPECT_EQ(chunks[0].size(), p::frame_size(12));
    EXPECT_EQ(f.next_flush(), Duration::max());
}

TEST(FaultInjector, NoiseArrivesAtItsRateAndOnlyCostsGarbage) {
    FaultOptions o;
    o.noise_bytes_per_s = 1000;
    FaultInjector f(o);
    std::vector<Chunk> all;
    for (int i = 1; i <= 50; ++i) {  // 1 s of 50 Hz frames
        auto c = f.shape(attitude_frames(1), i * 20ms);
        all.insert(all.end(), c.begin(), c.end());
    }
    EXPECT_NEAR(static_cast<double>(f.stats().noise_bytes), 1000.0, 1.0);
    std::size_t frames = 0;
    const auto stats = decode(all, &frames);
    EXPECT_GE(stats.garbage_bytes, 900U);
    EXPECT_GE(frames, 40U);  // a false 0xAE may swallow the odd frame, never most
}

TEST(FaultInjector, CorruptedFramesFailTheirCrc) {
    FaultOptions o;
    o.corrupt_fraction = 1.0;
    FaultInjector f(o);
    std::size_t frames = 0;
    const auto stats = decode(f.shape(attitude_frames(10), 20ms), &frames);
    EXPECT_EQ(frames, 0U);
    EXPECT_EQ(stats.crc_errors, 10U);
    EXPECT_EQ(f.stats().corrupted_frames, 10U);
}

TEST(FaultInjector, APartialFractionCorruptsSomeFramesReproducibly) {
    FaultOptions o;
    o.corrupt_fraction = 0.25;
    FaultInjector a(o);
    FaultInjector b(o);
    const auto frames = attitude_frames(400);
    EXPECT_EQ(a.shape(frames, 1s), b.shape(frames, 1s));  // same seed, same faults
    EXPECT_GT(a.stats().corrupted_frames, 50U);
    EXPECT_LT(a.stats().corrupted_frames, 150U);
}

TEST(FaultWindow, AlternatesBetweenNormalAndFault) {
    const FaultWindow w(1000ms, 300ms);
    EXPECT_FALSE(w.active(999ms));
    EXPECT_TRUE(w.active(1000ms));
    EXPECT_TRUE(w.active(1299ms));
    EXPECT_FALSE(w.active(1300ms));
    EXPECT_TRUE(w.active(2400ms));
    EXPECT_EQ(w.next_change(500ms), 1000ms);
    EXPECT_EQ(w.next_change(1000ms), 1300ms);
    EXPECT_EQ(w.next_change(1300ms), 2300ms);
    EXPECT_FALSE(FaultWindow(0ms, 0ms).active(5s));
}

TEST(FaultSchedule, ReportsEachTransitionOnce) {
    FaultOptions o;
    o.silence_every = 100ms;
    o.silence_for = 50ms;
    FaultSchedule s(o);
    using E = FaultSchedule::Event;
    EXPECT_TRUE(s.update(50ms).empty());
    EXPECT_EQ(s.update(110ms), std::vector<E>{E::kSilenceStart});
    EXPECT_TRUE(s.silent());
    EXPECT_TRUE(s.update(120ms).empty());
    EXPECT_EQ(s.update(160ms), std::vector<E>{E::kSilenceEnd});
    EXPECT_EQ(s.next_change(160ms), 250ms);

    FaultOptions v;
    v.vanish_every = 1000ms;
    v.vanish_for = 200ms;
    FaultSchedule t(v);
    EXPECT_TRUE(t.update(900ms).empty());
    EXPECT_EQ(t.update(1010ms), std::vector<E>{E::kVanish});
    EXPECT_TRUE(t.vanished());
    EXPECT_FALSE(t.silent());
    EXPECT_EQ(t.update(1210ms), std::vector<E>{E::kReappear});
    EXPECT_STREQ(to_string(E::kReappear), "reappear");
}

TEST(FaultOptionsCheck, RefusesHalfAWindowAndBadFractions) {
    FaultOptions o;
    o.silence_every = 100ms;
    EXPECT_TRUE(validate(o).has_value());
    o = {};
    o.corrupt_fraction = 1.5;
    EXPECT_TRUE(validate(o).has_value());
    o = {};
    o.shape = WriteShape::kMerge;
    o.merge_count = 1;
    EXPECT_TRUE(validate(o).has_value());
    EXPECT_FALSE(validate(FaultOptions{}).has_value());
}

}  // namespace
}  // namespace gport::sim
