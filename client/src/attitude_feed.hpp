// The shared-memory attitude channel merged into a reader's own poll: the
// one implementation behind Client::subscribe and AsyncClient::async_subscribe
// with shared_memory (docs/client-cpp.md, "Transparently") and gportctl
// watch --shared-memory.
//
// A waiter thread sleeps on the connection's futex word (passing wakes on
// like any reader of this process) and makes fd() readable whenever the
// word changes: a sample, or the close. The consumer polls fd() with its
// socket (Connection::watch: read() then returns kWoken; or an Asio
// descriptor), calls reset() and then take() until it is empty. Nothing
// polls on a timer: an idle feed costs the waiter one wake per 500 ms.
//
//     AttitudeFeed feed(connection.attitude_channel());
//     connection.watch(feed.fd());
//     ... read() == kWoken: feed.reset(); while (auto s = feed.take()) { ... }
//     connection.watch(-1);  // before the feed goes
//
// Internal to the library (not installed): exported for its own tests.
#pragma once

#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "gport/client/attitude_channel.hpp"
#include "gport/client/export.hpp"
#include "gport/client/types.hpp"

namespace gport::client {

class RingWaker;

class GPORT_CLIENT_API AttitudeFeed {
  public:
    // Takes the channel; take() gives the samples published from now on,
    // each once (those a slow reader skipped are counted in `dropped`).
    // Starts the waiter thread; throws Error (kTransport) when it cannot
    // make its eventfd.
    explicit AttitudeFeed(AttitudeChannel channel);
    AttitudeFeed(const AttitudeFeed&) = delete;
    AttitudeFeed& operator=(const AttitudeFeed&) = delete;
    // Stops the waiter (one futex wake); unwatch fd() first.
    ~AttitudeFeed();

    // Readable when the channel changed since the last reset() (it starts
    // readable, so the consumer looks once).
    int fd() const noexcept;
    // Before taking: a sample published after this call makes fd()
    // readable again.
    void reset() noexcept;
    // The next new sample without waiting; empty when there is none.
    std::optional<AttitudeSample> take();
    // gportd stopped publishing (it is shutting down).
    bool closed() const { return channel_.closed(); }

  private:
    AttitudeChannel channel_;
    std::unique_ptr<RingWaker> waker_;
};

// The attitude notification gportd sends on its socket for this sample
// (docs/api.md): the same members and values (whole numbers as integers,
// as gportd prints them; "dropped" only when some were missed). For tools
// that print what the socket would have carried (gportctl watch --json).
GPORT_CLIENT_API nlohmann::json attitude_notification(const AttitudeSample& sample);

}  // namespace gport::client
