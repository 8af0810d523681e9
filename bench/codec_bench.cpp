// Encoder frames/s for the two hot messages, and the fast CRC against the
// seed's byte-at-a-time reference.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <numeric>
#include <vector>

#include "gport/protocol/crc32.hpp"
#include "gport/protocol/messages.hpp"

namespace gp = gport::protocol;

namespace {

void BM_EncodeControl(benchmark::State& state) {
    std::int16_t yaw = 0;
    for (auto _ : state) {
        const gp::Frame f = gp::encode(gp::Control::speed_of({0, 0, yaw++}));
        benchmark::DoNotOptimize(f.bytes().data());
    }
    state.SetItemsProcessed(state.iterations());
}

void BM_EncodeAttitude(benchmark::State& state) {
    const bool with_rates = state.range(0) == gp::kAttitudeWithRatesSize;
    std::int16_t v = 0;
    for (auto _ : state) {
        gp::Attitude a{{v, 1, 2}, {3, 4, 5}, std::nullopt};
        if (with_rates) {
            a.rates = gp::AttitudeRates{{6, 7, 8}, 9, 10, v};
        }
        ++v;
        const gp::Frame f = gp::encode(a);
        benchmark::DoNotOptimize(f.bytes().data());
    }
    state.SetItemsProcessed(state.iterations());
}

std::vector<std::uint8_t> crc_input(std::size_t n) {
    std::vector<std::uint8_t> data(n);
    std::iota(data.begin(), data.end(), std::uint8_t{7});
    return data;
}

template <std::uint32_t (*Crc)(std::span<const std::uint8_t>)>
void BM_Crc(benchmark::State& state) {
    const auto data = crc_input(static_cast<std::size_t>(state.range(0)));
    for (auto _ : state) {
        benchmark::DoNotOptimize(Crc(data));
    }
    state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * data.size()));
}

std::uint32_t fast(std::span<const std::uint8_t> d) {
    return gp::crc32(d);
}
std::uint32_t reference(std::span<const std::uint8_t> d) {
    return gp::crc32_reference(d);
}

}  // namespace

BENCHMARK(BM_EncodeControl);
BENCHMARK(BM_EncodeAttitude)->Arg(gp::kAttitudeSize)->Arg(gp::kAttitudeWithRatesSize);
BENCHMARK(BM_Crc<fast>)->Name("BM_Crc32Fast")->Arg(12)->Arg(255)->Arg(4096);
BENCHMARK(BM_Crc<reference>)->Name("BM_Crc32Reference")->Arg(12)->Arg(255)->Arg(4096);
