// gport-mavlink's MAVLink side: one UDP socket or a serial port, read into a
// fixed buffer (bounded work per read).
//
//   udpin   bound to ADDR:PORT, exclusively (no SO_REUSEADDR: nobody else,
//           whatever their uid, can bind it beside us). Replies go to the
//           PEER: the sender of the last datagram that held a frame the
//           bridge ACCEPTED (signature and trust rules passed;
//           accept_sender()), never to whoever merely sends a datagram.
//           Until one is accepted, nothing is sent.
//   udpout  sends to ADDR:PORT from an ephemeral port, the socket
//           connect()ed to it, so the kernel drops datagrams from anyone
//           else.
//   serial  a UART, 8N1, no flow control.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include "gport/mavlink/bridge/options.hpp"

namespace gport::mavlink::bridge {

// Where a chunk came from: its UDP sender for udpin; empty for udpout and
// serial, whose peer is fixed.
using Origin = std::optional<boost::asio::ip::udp::endpoint>;

class Transport {
  public:
    // `fresh_source`: the chunk does not continue the previous one's byte
    // stream (another UDP sender than the last datagram's): the receiver
    // forgets any partial frame, so that no frame is made of two senders'
    // bytes and every frame has one sender.
    using Receiver = std::function<void(std::span<const std::uint8_t>, bool fresh_source)>;
    virtual ~Transport() = default;
    // Starts reading; `receive` gets each chunk read (at most kReadSize bytes).
    virtual void start(Receiver receive) = 0;
    // Sends one frame; dropped (and counted) when there is nobody to send to
    // yet (udpin before the first accepted frame) or the send fails.
    virtual void send(std::span<const std::uint8_t> frame) = 0;
    // Sends a reply to the origin of an accepted request (udpin: the
    // request's sender, which may not be the current peer any more); to the
    // peer when the origin is empty.
    virtual void send_to(std::span<const std::uint8_t> frame, const Origin& origin) {
        (void)origin;
        send(frame);
    }
    // The origin of the chunk being delivered (valid during the callback).
    virtual Origin origin() const { return std::nullopt; }
    // Called while a chunk is delivered, for a frame in it that was
    // accepted: udpin makes its sender the peer and, when that changed the
    // peer, returns the new one ("ADDR:PORT") for the Bridge to log;
    // nothing for the others.
    virtual std::optional<std::string> accept_sender() { return std::nullopt; }
    // True when a frame for `to` (a reply's origin, or empty: the peer)
    // would go out: false for udpin before the first accepted frame. The
    // Bridge asks before it signs, so that no timestamp is spent (and
    // reserved in the timestamp file) on a frame that is not sent.
    virtual bool can_send(const Origin& to) const {
        (void)to;
        return true;
    }
    // Counts a frame dropped for want of a peer (can_send() said no).
    void count_unsent() { ++unsent_; }
    std::uint64_t send_failures() const { return send_failures_; }
    std::uint64_t unsent() const { return unsent_; }

    static constexpr std::size_t kReadSize = 2048;

  protected:
    std::uint64_t send_failures_ = 0;
    std::uint64_t unsent_ = 0;  // dropped for want of a peer
};

// Opens the endpoint; throws std::runtime_error naming it and the cause.
std::unique_ptr<Transport> open_transport(boost::asio::io_context& io, const Endpoint& endpoint);

}  // namespace gport::mavlink::bridge
