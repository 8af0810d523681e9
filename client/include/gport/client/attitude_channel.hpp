// gport::client::AttitudeChannel: gportd's shared-memory attitude channel
// (docs/api.md, "Shared-memory attitude channel"). gportd hands the client
// a read-only memory block holding a ring of the latest attitude samples and
// wakes its readers once per sample, so its own cost does not grow with
// what the reader does; a reader that falls more than a ring behind skips
// samples (counted by missed()) and never slows gportd or anyone else.
//
//     auto gimbal = gport::client::Client::connect();
//     auto channel = gimbal.attitude_channel();
//     while (auto sample = channel.next(std::chrono::seconds(1))) { ... }
//
// The channel stays readable after its Client is closed or destroyed (it
// is this process's mapping); closed() turns true when gportd stops.
// Thread-safety: one thread per AttitudeChannel (next() moves its cursor);
// latest(), missed() and closed() may be called from any thread.
//
// ABI: a pimpl; movable, not copyable.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>

#include "gport/client/export.hpp"
#include "gport/client/types.hpp"

namespace gport::client {

class GPORT_CLIENT_API AttitudeChannel {
  public:
    // An empty channel: next() and latest() give nothing, closed() is true.
    AttitudeChannel();
    AttitudeChannel(AttitudeChannel&& other) noexcept;
    AttitudeChannel& operator=(AttitudeChannel&& other) noexcept;
    AttitudeChannel(const AttitudeChannel&) = delete;
    AttitudeChannel& operator=(const AttitudeChannel&) = delete;
    ~AttitudeChannel();

    // The next sample after the last one taken, waiting at most `timeout`
    // for it; the first call gives the newest. Empty on timeout, or once the
    // channel is closed and every sample was taken. `dropped` in the sample
    // is missed() at that point.
    std::optional<AttitudeSample> next(std::chrono::milliseconds timeout);
    // The newest sample (the cursor of next() does not move); empty before
    // the first one.
    std::optional<AttitudeSample> latest() const;
    // Samples next() skipped because this reader fell more than a ring behind.
    std::uint64_t missed() const;
    // gportd stopped publishing (it is shutting down), or the channel is empty.
    bool closed() const;

    struct Impl;
    // Used by Client and AsyncClient (the library's own).
    explicit AttitudeChannel(std::unique_ptr<Impl> impl);
    Impl* impl() noexcept { return impl_.get(); }

  private:
    std::unique_ptr<Impl> impl_;
};

}  // namespace gport::client
