// Fault injection for the simulated gimbal, pure and seeded.
//
// FaultInjector turns the frames the model sends into the write() calls the
// simulator makes: it adds noise bytes, corrupts CRCs, and splits or merges
// writes. FaultSchedule says when the link is silent (output dropped) or has
// vanished (pty closed, as an unplugged USB adapter). Both run on the same
// model time as GimbalModel, so tests can step them deterministically.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "gport/protocol/frame.hpp"
#include "gport/sim/model.hpp"

namespace gport::sim {

enum class WriteShape {
    kWhole,  // one write per frame (and one per noise run)
    kSplit,  // one write per byte
    kMerge,  // several frames per write
};

struct FaultOptions {
    double noise_bytes_per_s = 0.0;  // random bytes inserted between frames
    double corrupt_fraction = 0.0;   // 0..1: share of frames sent with a wrong CRC
    WriteShape shape = WriteShape::kWhole;
    unsigned merge_count = 4;  // kMerge: frames per write
    // kMerge: a partial group waits at most this long (so replies still go out).
    Duration merge_max_wait = std::chrono::milliseconds(100);
    Duration silence_every{0};  // after this much talking...
    Duration silence_for{0};    // ...say nothing for this long (0: never)
    Duration vanish_every{0};   // after this long present...
    Duration vanish_for{0};     // ...close the pty for this long (0: never)
    std::uint32_t seed = 1;     // for noise and corruption
};

// Empty when usable; otherwise what is wrong and what is allowed.
std::optional<std::string> validate(const FaultOptions& options);

struct FaultStats {
    std::uint64_t noise_bytes = 0;
    std::uint64_t corrupted_frames = 0;
};

using Chunk = std::vector<std::uint8_t>;  // the bytes of one write()

class FaultInjector {
  public:
    explicit FaultInjector(FaultOptions options);

    // The writes to make at model time `now` for these frames (which may be
    // none: noise and held merge groups are released by time too).
    std::vector<Chunk> shape(std::span<const protocol::Frame> frames, Duration now);
    // When a held merge group must go out; Duration::max() when none is held.
    Duration next_flush() const;
    const FaultStats& stats() const { return stats_; }

  private:
    std::vector<Chunk> units(std::span<const protocol::Frame> frames, Duration now);
    std::vector<Chunk> merge(std::vector<Chunk> units, Duration now);

    FaultOptions options_;
    std::mt19937 rng_;
    FaultStats stats_;
    Duration last_{0};
    double noise_owed_ = 0.0;
    Chunk held_;
    unsigned held_frames_ = 0;
    Duration held_since_{0};
};

// A repeating window: `every` of normal time, then `length` of fault.
class FaultWindow {
  public:
    FaultWindow(Duration every, Duration length) : every_(every), length_(length) {}
    bool enabled() const { return length_ > Duration::zero(); }
    bool active(Duration now) const;
    // The next time after `now` at which active() changes; max() when disabled.
    Duration next_change(Duration now) const;

  private:
    Duration every_;
    Duration length_;
};

class FaultSchedule {
  public:
    enum class Event { kSilenceStart, kSilenceEnd, kVanish, kReappear };

    explicit FaultSchedule(const FaultOptions& options);
    // The transitions since the previous call, in order of kind.
    std::vector<Event> update(Duration now);
    bool silent() const { return silent_; }
    bool vanished() const { return vanished_; }
    Duration next_change(Duration now) const;

  private:
    FaultWindow silence_;
    FaultWindow vanish_;
    bool silent_ = false;
    bool vanished_ = false;
};

const char* to_string(FaultSchedule::Event event);

}  // namespace gport::sim
