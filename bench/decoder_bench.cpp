// Decoder throughput in bytes/s: clean input (a realistic mix, mostly 0x87
// attitude reports), input that is half garbage rich in 0xAE, and input that
// is half uniform line noise; fed in 4 KiB chunks (a busy read()) and in
// 64-byte chunks (a UART FIFO's worth).
#include <benchmark/benchmark.h>

#include <cstdint>
#include <random>
#include <span>
#include <vector>

#include "gport/protocol/decoder.hpp"
#include "gport/protocol/messages.hpp"

namespace gp = gport::protocol;

namespace {

using Bytes = std::vector<std::uint8_t>;

constexpr std::size_t kStreamSize = 1 << 20;  // 1 MiB per iteration

void append(Bytes& out, const gp::Frame& f) {
    out.insert(out.end(), f.bytes().begin(), f.bytes().end());
}

std::int16_t centi(std::mt19937& rng) {
    return static_cast<std::int16_t>(std::uniform_int_distribution<int>(-18000, 18000)(rng));
}

// What a gimbal link carries: attitude reports (both forms), with the odd
// settings report and acknowledgement, and commands echoed back in tests.
gp::Frame realistic_frame(std::mt19937& rng) {
    const int pick = std::uniform_int_distribution<int>(0, 99)(rng);
    const gp::Axes a{centi(rng), centi(rng), centi(rng)};
    if (pick < 60) {
        return gp::encode(gp::Attitude{a, a, std::nullopt});
    }
    if (pick < 90) {
        return gp::encode(gp::Attitude{a, a, gp::AttitudeRates{a, 1, 2, 3}});
    }
    if (pick < 95) {
        return gp::encode(gp::Control::speed_of(a));
    }
    if (pick < 98) {
        return gp::encode(gp::SettingsReport{});
    }
    return gp::encode(gp::SetSettingsAck{});
}

enum class Noise { kRandom, kHeaderRich };

// kRandom is line noise (uniform bytes). kHeaderRich is the hostile case: a
// third of it 0xAE and a third the version byte, so one byte in three is a
// candidate the decoder must judge and reject.
void append_noise(Bytes& out, std::size_t n, Noise noise, std::mt19937& rng) {
    std::uniform_int_distribution<int> byte(0, 255);
    std::uniform_int_distribution<int> kind(0, 2);
    for (std::size_t i = 0; i < n; ++i) {
        const int k = noise == Noise::kHeaderRich ? kind(rng) : 2;
        out.push_back(k == 0 ? 0xAE : k == 1 ? 0x01 : static_cast<std::uint8_t>(byte(rng)));
    }
}

Bytes make_stream(double garbage_share, Noise noise = Noise::kHeaderRich) {
    std::mt19937 rng(12345);
    Bytes out;
    out.reserve(kStreamSize + gp::kMaxFrameSize * 2);
    std::size_t garbage = 0;
    while (out.size() < kStreamSize) {
        append(out, realistic_frame(rng));
        // Keep the garbage share at the target, in chunks of up to 40 bytes.
        const auto want = static_cast<std::size_t>(garbage_share * static_cast<double>(out.size()));
        if (want > garbage) {
            const std::size_t n = std::min<std::size_t>(want - garbage, 40);
            append_noise(out, n, noise, rng);
            garbage += n;
        }
    }
    return out;
}

void run_decoder(benchmark::State& state, const Bytes& stream) {
    const auto chunk = static_cast<std::size_t>(state.range(0));
    std::uint64_t frames = 0;
    for (auto _ : state) {
        gp::Decoder dec;
        const std::span<const std::uint8_t> all(stream);
        for (std::size_t pos = 0; pos < all.size(); pos += chunk) {
            dec.feed(all.subspan(pos, std::min(chunk, all.size() - pos)),
                     [&](const gp::FrameView& f) { frames += f.command; });
        }
        benchmark::DoNotOptimize(frames);
        state.counters["garbage_share"] =
            static_cast<double>(dec.stats().garbage_bytes) / static_cast<double>(dec.stats().bytes);
    }
    state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * stream.size()));
}

void BM_DecodeClean(benchmark::State& state) {
    static const Bytes stream = make_stream(0.0);
    run_decoder(state, stream);
}

void BM_DecodeHalfGarbage(benchmark::State& state) {
    static const Bytes stream = make_stream(0.5);
    run_decoder(state, stream);
}

void BM_DecodeHalfRandomNoise(benchmark::State& state) {
    static const Bytes stream = make_stream(0.5, Noise::kRandom);
    run_decoder(state, stream);
}

}  // namespace

BENCHMARK(BM_DecodeClean)->Arg(4096)->Arg(64);
BENCHMARK(BM_DecodeHalfGarbage)->Arg(4096)->Arg(64);
BENCHMARK(BM_DecodeHalfRandomNoise)->Arg(4096)->Arg(64);
