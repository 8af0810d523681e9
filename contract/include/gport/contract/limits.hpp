// The ranges and limits of the client API (docs/api.md) that a request is
// checked against, on both sides: gportd refuses what is outside them
// (-32602, naming the range), gportctl refuses it before sending.
//
// Standard C++17.
#pragma once

#include <cstddef>
#include <cstdint>

namespace gport::contract {

// Angles (degrees) and speeds (degrees per second) on every axis: what the
// gimbal's int16 in 0.01 units carries without wrapping (±32767; the wire's
// -32768 is refused too, so the range is symmetric). Also the soft limits'
// defaults (limits.*: no limit) and the simulator's fastest slew.
inline constexpr double kMaxDegrees = 327.67;

// The longest duration_ms and lease_ms a client sends (a day): gportctl
// refuses a longer --for or --lease before connecting. gportd's own bound is
// its keepalive.max_duration_ms (at most 600 000), named in its refusal.
inline constexpr std::int64_t kMaxDurationMs = 86'400'000;

// subscribe's max_rate_hz. Slower than one sample in 100 s is not a rate
// anyone needs, and keeps the interval far from overflowing a clock duration.
inline constexpr double kMinRateHz = 0.01;
inline constexpr double kMaxRateHz = 1000.0;

// A request line: nesting deeper than this is refused (-32700) before it is
// parsed; a batch holds at most kMaxBatch members; a string id is at most
// kMaxIdLength bytes (-32600 beyond).
inline constexpr std::size_t kMaxDepth = 64;
inline constexpr std::size_t kMaxBatch = 32;
inline constexpr std::size_t kMaxIdLength = 128;

}  // namespace gport::contract
