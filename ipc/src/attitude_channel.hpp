// The daemon's end of the shared-memory attitude channel (docs/api.md,
// "Shared-memory attitude channel"): one sealed memfd holding a
// base::RingWriter ring, made on the first request and shared by every
// client that asks for it.
//
//   AttitudeChannel channel;
//   if (auto error = channel.open()) { ... -32603 "attitude channel unavailable: " + *error }
//   send channel.fd() to the client (SCM_RIGHTS);
//   channel.publish(sample);      // every 0x87 sample, then
//   channel.wake();               // only while a connected client opened it
//   channel.close();              // on shutdown: readers see closed(), waiters wake
//
// The block is mapped read-write here and sealed afterwards (F_SEAL_SHRINK,
// F_SEAL_GROW, F_SEAL_FUTURE_WRITE, F_SEAL_SEAL): this mapping keeps writing,
// while every other mapping of the descriptor can only be read-only.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "gport/base/attitude_ring.hpp"
#include "gport/daemon/events.hpp"

namespace gport::ipc::detail {

// The start of every -32603 message about the channel.
inline constexpr std::string_view kUnavailable = "attitude channel unavailable: ";

// A sample as the ring carries it: the attitude notification's values.
base::RingSample ring_sample(const daemon::AttitudeSample& sample);

class AttitudeChannel {
  public:
    static constexpr std::uint32_t kSlots = 64;
    static constexpr std::size_t kBytes = base::ring_bytes(kSlots);

    AttitudeChannel() = default;
    ~AttitudeChannel();
    AttitudeChannel(const AttitudeChannel&) = delete;
    AttitudeChannel& operator=(const AttitudeChannel&) = delete;

    // Makes the block the first time (later calls do nothing). The error
    // names the step that failed and why; nothing is kept then, so the next
    // call tries again.
    std::optional<std::string> open();

    // The sealed memfd (-1 before open()); it stays open until destruction.
    int fd() const { return fd_; }
    std::uint64_t published() const { return writer_ ? writer_->published() : 0; }

    // Writes one sample into the ring; nothing before open() or after close().
    void publish(const daemon::AttitudeSample& sample);
    // Wakes every reader waiting on the futex word.
    void wake();
    // No more samples: sets the closed flag and wakes every waiter. Idempotent.
    void close();

  private:
    int fd_ = -1;
    void* memory_ = nullptr;
    std::optional<base::RingWriter> writer_;
    bool closed_ = false;
};

}  // namespace gport::ipc::detail
