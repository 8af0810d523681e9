// The capture log's cost (docs/operations.md, "The capture log"): what the
// event loop pays per capture (the capture made, indexed, kept, serialized and
// queued) and what the writer thread pays per capture on a disk (write and
// fdatasync, with the hand-over between the threads).
//   bench_captures [--benchmark_filter=...]   GPORT_BENCH_DIR: the disk to
//   write on (default /var/tmp, which is rarely a tmpfs)
#include <benchmark/benchmark.h>
#include <spdlog/logger.h>
#include <spdlog/sinks/null_sink.h>
#include <stdlib.h>

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <variant>

#include "gport/capture/capture_log.hpp"
#include "gport/capture/capture_writer.hpp"
#include "process.hpp"

namespace {

using nlohmann::json;

json sample_capture() {
    return json{{"utc_us", 1795563183085470},
                {"mono_us", 24172367794},
                {"attitude",
                 {{"imu", {{"roll", 0.12}, {"pitch", -30.05}, {"yaw", 12.5}}},
                  {"hall", {{"roll", 0.1}, {"pitch", -29.98}, {"yaw", 45.01}}},
                  {"age_ms", 7}}},
                {"client", {{"pid", 1234}, {"uid", 0}, {"name", "gport-mavlink"}}},
                {"meta", {{"lat", 47.397742}, {"lon", 8.545594}, {"alt_m", 488.5}}}};
}

std::shared_ptr<spdlog::logger> quiet() {
    return std::make_shared<spdlog::logger>("bench",
                                            std::make_shared<spdlog::sinks::null_sink_mt>());
}

// The capture log's directory on a real disk: GPORT_BENCH_DIR, or /var/tmp
// (/tmp may be a tmpfs, where fdatasync costs nothing); made fresh, removed
// with what the benchmark wrote.
gport::testing::TempDir bench_dir() {
    const char* base = std::getenv("GPORT_BENCH_DIR");
    return gport::testing::TempDir("gport-bench", base != nullptr ? base : "/var/tmp");
}

// The loop's share: add() builds the line and queues it (the writer drains
// in the background, so the queue never fills here).
void BM_CaptureOnTheLoop(benchmark::State& state) {
    const auto dir = bench_dir();
    gport::capture::CaptureWriter writer({dir.path(), 64 << 20, 2}, 1001, quiet(), 1 << 20);
    gport::capture::CaptureLog log;
    log.set_sink(&writer);
    const auto capture = sample_capture();
    for (auto _ : state) {
        auto prepared = log.prepare(capture);
        if (!std::holds_alternative<gport::capture::CaptureLog::Prepared>(prepared)) {
            // Faster than the writer moves the durable mark (a real camera
            // takes a few a second): let it catch up, untimed.
            state.PauseTiming();
            writer.drain();
            state.ResumeTiming();
            prepared = log.prepare(capture);
        }
        benchmark::DoNotOptimize(
            log.add(std::get<gport::capture::CaptureLog::Prepared>(std::move(prepared)), "photo"));
    }
    writer.drain();
}
BENCHMARK(BM_CaptureOnTheLoop);

// One `captures` page on the loop (limit 1000) over 1,000 kept captures
// with 1 KiB metas: the page is spliced from the kept text and bounded by
// bytes (CaptureLog::kMaxPageBytes), whatever the log holds.
void BM_CapturesPageOnTheLoop(benchmark::State& state) {
    gport::capture::CaptureLog log;
    auto capture = sample_capture();
    capture["meta"]["note"] = std::string(960, 'x');
    for (int i = 0; i < 1000; ++i) {
        log.add(std::get<gport::capture::CaptureLog::Prepared>(log.prepare(capture)), "photo");
    }
    std::size_t bytes = 0;
    for (auto _ : state) {
        const auto page = log.list(0, gport::capture::CaptureLog::kMaxLimit);
        bytes = page.size();
        benchmark::DoNotOptimize(page.data());
    }
    state.counters["page_bytes"] = static_cast<double>(bytes);
}
BENCHMARK(BM_CapturesPageOnTheLoop);

// The writer's share: a burst of 1000 captures queued, written and
// fdatasync'd in groups (at most every 100 ms: the time per burst is at
// least that), waited for.
void BM_CaptureToDisk(benchmark::State& state) {
    constexpr int kBurst = 1000;
    const auto dir = bench_dir();
    gport::capture::CaptureWriter writer({dir.path(), 64 << 20, 2}, 1001, quiet(), kBurst);
    const auto line = json(sample_capture()).dump();
    for (auto _ : state) {
        for (int i = 0; i < kBurst; ++i) {
            writer.write(line);
        }
        writer.drain();
    }
    state.SetItemsProcessed(state.iterations() * kBurst);
    state.counters["dropped"] = static_cast<double>(writer.stats().dropped);
}
BENCHMARK(BM_CaptureToDisk)->UseRealTime();

// A photo flood: 1300 captures a second for 3 s, paced, through the
// daemon's queue (256 lines). "dropped" is what the disk could not keep up
// with (one fdatasync per capture kept up with 1160/s on the development
// VM's ext4, so it dropped here).
void BM_CaptureFlood(benchmark::State& state) {
    constexpr int kPerSecond = 1300;
    constexpr int kSeconds = 3;
    const auto dir = bench_dir();
    const auto line = json(sample_capture()).dump();
    std::uint64_t dropped = 0;
    for (auto _ : state) {
        gport::capture::CaptureWriter writer({dir.path(), 64 << 20, 2}, 1001, quiet());
        auto next = std::chrono::steady_clock::now();
        for (int i = 0; i < kPerSecond * kSeconds; ++i) {
            writer.write(line);
            next += std::chrono::microseconds(1000000 / kPerSecond);
            std::this_thread::sleep_until(next);
        }
        writer.drain();
        dropped += writer.stats().dropped;
    }
    state.counters["dropped"] = static_cast<double>(dropped);
    state.counters["dropped_pct"] = 100.0 * static_cast<double>(dropped) /
                                    static_cast<double>(kPerSecond * kSeconds * state.iterations());
}
BENCHMARK(BM_CaptureFlood)->Iterations(2)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace
