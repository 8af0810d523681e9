#include "gport/sim/faults.hpp"

#include <algorithm>
#include <cmath>

namespace gport::sim {

std::optional<std::string> validate(const FaultOptions& o) {
    if (!std::isfinite(o.noise_bytes_per_s) || o.noise_bytes_per_s < 0 ||
        o.noise_bytes_per_s > 1e6) {
        return "noise must be from 0 to 1000000 bytes per second";
    }
    if (!std::isfinite(o.corrupt_fraction) || o.corrupt_fraction < 0 || o.corrupt_fraction > 1) {
        return "corrupt fraction must be from 0 to 1";
    }
    if (o.shape == WriteShape::kMerge && o.merge_count < 2) {
        return "merge needs at least 2 frames per write";
    }
    const auto window_ok = [](Duration every, Duration length) {
        return (every == Duration::zero()) == (length == Duration::zero()) &&
               every >= Duration::zero() && length >= Duration::zero();
    };
    if (!window_ok(o.silence_every, o.silence_for)) {
        return "silence needs both 'every' and 'for' above 0 milliseconds";
    }
    if (!window_ok(o.vanish_every, o.vanish_for)) {
        return "vanish needs both 'every' and 'for' above 0 milliseconds";
    }
    return std::nullopt;
}

FaultInjector::FaultInjector(FaultOptions options) : options_(options), rng_(options.seed) {}

// Noise first (it builds up between frames), then each frame, CRC corrupted
// with the configured probability; each is one unit of output.
std::vector<Chunk> FaultInjector::units(std::span<const protocol::Frame> frames, Duration now) {
    std::vector<Chunk> out;
    if (options_.noise_bytes_per_s > 0 && now > last_) {
        noise_owed_ +=
            options_.noise_bytes_per_s * std::chrono::duration<double>(now - last_).count();
        const auto n = static_cast<std::size_t>(noise_owed_);
        noise_owed_ -= static_cast<double>(n);
        if (n > 0) {
            std::uniform_int_distribution<int> byte(0, 255);
            Chunk noise(n);
            std::generate(noise.begin(), noise.end(),
                          [&] { return static_cast<std::uint8_t>(byte(rng_)); });
            stats_.noise_bytes += n;
            out.push_back(std::move(noise));
        }
    }
    last_ = std::max(last_, now);
    std::bernoulli_distribution corrupt(options_.corrupt_fraction);
    for (const auto& frame : frames) {
        Chunk bytes(frame.bytes().begin(), frame.bytes().end());
        if (options_.corrupt_fraction > 0 && frame.data().size() > 0 && corrupt(rng_)) {
            bytes.back() ^= 0x5A;  // the CRC's top byte: header intact, CRC wrong
            ++stats_.corrupted_frames;
        }
        out.push_back(std::move(bytes));
    }
    return out;
}

std::vector<Chunk> FaultInjector::merge(std::vector<Chunk> units, Duration now) {
    std::vector<Chunk> out;
    for (auto& unit : units) {
        if (held_.empty()) {
            held_since_ = now;
        }
        held_.insert(held_.end(), unit.begin(), unit.end());
        if (++held_frames_ >= options_.merge_count) {
            out.push_back(std::move(held_));
            held_.clear();
            held_frames_ = 0;
        }
    }
    if (!held_.empty() && now >= held_since_ + options_.merge_max_wait) {
        out.push_back(std::move(held_));
        held_.clear();
        held_frames_ = 0;
    }
    return out;
}

std::vector<Chunk> FaultInjector::shape(std::span<const protocol::Frame> frames, Duration now) {
    auto out = units(frames, now);
    switch (options_.shape) {
        case WriteShape::kWhole:
            return out;
        case WriteShape::kMerge:
            return merge(std::move(out), now);
        case WriteShape::kSplit: {
            std::vector<Chunk> bytes;
            for (const auto& unit : out) {
                for (auto b : unit) {
                    bytes.push_back(Chunk{b});
                }
            }
            return bytes;
        }
    }
    return out;
}

Duration FaultInjector::next_flush() const {
    return held_.empty() ? Duration::max() : held_since_ + options_.merge_max_wait;
}

bool FaultWindow::active(Duration now) const {
    if (!enabled() || now < Duration::zero()) {
        return false;
    }
    return now % (every_ + length_) >= every_;
}

Duration FaultWindow::next_change(Duration now) const {
    if (!enabled()) {
        return Duration::max();
    }
    const Duration cycle = every_ + length_;
    const Duration start = now - now % cycle;
    const Duration pos = now - start;
    return pos < every_ ? start + every_ : start + cycle;
}

FaultSchedule::FaultSchedule(const FaultOptions& o)
    : silence_(o.silence_every, o.silence_for), vanish_(o.vanish_every, o.vanish_for) {}

std::vector<FaultSchedule::Event> FaultSchedule::update(Duration now) {
    std::vector<Event> events;
    if (const bool s = silence_.active(now); s != silent_) {
        silent_ = s;
        events.push_back(s ? Event::kSilenceStart : Event::kSilenceEnd);
    }
    if (const bool v = vanish_.active(now); v != vanished_) {
        vanished_ = v;
        events.push_back(v ? Event::kVanish : Event::kReappear);
    }
    return events;
}

Duration FaultSchedule::next_change(Duration now) const {
    return std::min(silence_.next_change(now), vanish_.next_change(now));
}

const char* to_string(FaultSchedule::Event event) {
    switch (event) {
        case FaultSchedule::Event::kSilenceStart:
            return "silence_start";
        case FaultSchedule::Event::kSilenceEnd:
            return "silence_end";
        case FaultSchedule::Event::kVanish:
            return "vanish";
        case FaultSchedule::Event::kReappear:
            return "reappear";
    }
    return "unknown";
}

}  // namespace gport::sim
