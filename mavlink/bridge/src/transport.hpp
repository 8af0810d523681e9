// gport-mavlink's MAVLink side: one UDP socket (udpin: bound, answering the
// last sender; udpout: sending to a fixed address, receiving its replies) or
// a serial port, read into a fixed buffer (bounded work per read).
#pragma once

#include <boost/asio/io_context.hpp>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>

#include "gport/mavlink/bridge/options.hpp"

namespace gport::mavlink::bridge {

class Transport {
  public:
    using Receiver = std::function<void(std::span<const std::uint8_t>)>;
    virtual ~Transport() = default;
    // Starts reading; `receive` gets each chunk read (at most kReadSize bytes).
    virtual void start(Receiver receive) = 0;
    // Sends one frame; dropped (and counted) when there is nobody to send to
    // yet (udpin before the first datagram) or the send fails.
    virtual void send(std::span<const std::uint8_t> frame) = 0;
    // True once there is a peer to send to.
    virtual bool has_peer() const = 0;
    std::uint64_t send_failures() const { return send_failures_; }

    static constexpr std::size_t kReadSize = 2048;

  protected:
    std::uint64_t send_failures_ = 0;
};

// Opens the endpoint; throws std::runtime_error naming it and the cause.
std::unique_ptr<Transport> open_transport(boost::asio::io_context& io, const Endpoint& endpoint);

}  // namespace gport::mavlink::bridge
