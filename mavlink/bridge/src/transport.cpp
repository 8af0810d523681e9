#include "transport.hpp"

#include <spdlog/spdlog.h>

#include <array>
#include <boost/asio/ip/udp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/serial_port.hpp>
#include <boost/asio/write.hpp>
#include <stdexcept>
#include <string>
#include <vector>

namespace gport::mavlink::bridge {

namespace {

namespace asio = boost::asio;
using asio::ip::udp;

std::string text_of(const udp::endpoint& e) {
    return e.address().to_string() + ":" + std::to_string(e.port());
}

class UdpTransport final : public Transport {
  public:
    UdpTransport(asio::io_context& io, const Endpoint& e)
        : socket_(io), listening_(e.kind == Endpoint::Kind::kUdpIn) {
        boost::system::error_code ec;
        const auto address = asio::ip::make_address(e.address, ec);
        if (ec) {
            throw std::runtime_error(to_string(e) + ": \"" + e.address + "\" is not an IP address");
        }
        const udp::endpoint where(address, static_cast<unsigned short>(e.number));
        socket_.open(where.protocol());
        if (listening_) {
            // No SO_REUSEADDR: with it on both sockets, another uid could bind
            // the same address and take every datagram (transport.hpp).
            socket_.bind(where, ec);
            if (ec) {
                throw std::runtime_error(to_string(e) + ": cannot bind: " + ec.message());
            }
            return;
        }
        // Connected: the kernel delivers datagrams from `where` only.
        socket_.connect(where, ec);
        if (ec) {
            throw std::runtime_error(to_string(e) + ": cannot connect: " + ec.message());
        }
        peer_ = where;
    }

    void start(Receiver receive) override {
        receive_ = std::move(receive);
        read();
    }

    void send(std::span<const std::uint8_t> frame) override {
        if (!peer_) {
            ++unsent_;
            return;
        }
        boost::system::error_code ec;
        if (listening_) {
            socket_.send_to(asio::buffer(frame.data(), frame.size()), *peer_, 0, ec);
        } else {
            socket_.send(asio::buffer(frame.data(), frame.size()), 0, ec);
        }
        if (ec) {
            ++send_failures_;
            spdlog::debug("mavlink: send to {} failed: {}", text_of(*peer_), ec.message());
        }
    }

    void send_to(std::span<const std::uint8_t> frame, const Origin& origin) override {
        if (!listening_ || !origin) {
            send(frame);
            return;
        }
        boost::system::error_code ec;
        socket_.send_to(asio::buffer(frame.data(), frame.size()), *origin, 0, ec);
        if (ec) {
            ++send_failures_;
            spdlog::debug("mavlink: send to {} failed: {}", text_of(*origin), ec.message());
        }
    }

    Origin origin() const override { return listening_ ? Origin(sender_) : std::nullopt; }

    std::optional<std::string> accept_sender() override {
        if (!listening_ || (peer_ && *peer_ == sender_)) {
            return std::nullopt;
        }
        peer_ = sender_;
        return text_of(sender_);
    }

    bool can_send(const Origin& to) const override {
        return !listening_ || to.has_value() || peer_.has_value();
    }

  private:
    void read() {
        socket_.async_receive_from(
            asio::buffer(buffer_), sender_, [this](boost::system::error_code ec, std::size_t n) {
                if (ec == asio::error::operation_aborted) {
                    return;
                }
                if (!ec) {
                    const bool fresh = !last_sender_ || *last_sender_ != sender_;
                    last_sender_ = sender_;
                    receive_({buffer_.data(), n}, fresh);
                }
                // Re-armed through post: timers and gportd's replies get their turn
                // between datagrams of a flooding peer. (A connected socket may report
                // ECONNREFUSED here while the peer is not listening: read again.)
                asio::post(socket_.get_executor(), [this] { read(); });
            });
    }

    udp::socket socket_;
    bool listening_;
    udp::endpoint sender_;
    std::optional<udp::endpoint> last_sender_;
    std::optional<udp::endpoint> peer_;
    std::array<std::uint8_t, kReadSize> buffer_{};
    Receiver receive_;
};

class SerialTransport final : public Transport {
  public:
    SerialTransport(asio::io_context& io, const Endpoint& e) : port_(io) {
        boost::system::error_code ec;
        port_.open(e.address, ec);
        if (ec) {
            throw std::runtime_error(to_string(e) + ": cannot open " + e.address + ": " +
                                     ec.message());
        }
        port_.set_option(asio::serial_port::baud_rate(e.number), ec);
        if (ec) {
            throw std::runtime_error(to_string(e) + ": baud rate " + std::to_string(e.number) +
                                     " refused: " + ec.message());
        }
        port_.set_option(asio::serial_port::character_size(8));
        port_.set_option(asio::serial_port::parity(asio::serial_port::parity::none));
        port_.set_option(asio::serial_port::stop_bits(asio::serial_port::stop_bits::one));
        port_.set_option(asio::serial_port::flow_control(asio::serial_port::flow_control::none));
    }

    void start(Receiver receive) override {
        receive_ = std::move(receive);
        read();
    }

    void send(std::span<const std::uint8_t> frame) override {
        boost::system::error_code ec;
        asio::write(port_, asio::buffer(frame.data(), frame.size()), ec);
        if (ec) {
            ++send_failures_;
        }
    }

  private:
    void read() {
        port_.async_read_some(
            asio::buffer(buffer_), [this](boost::system::error_code ec, std::size_t n) {
                if (ec == asio::error::operation_aborted) {
                    return;
                }
                if (ec) {
                    throw std::runtime_error("mavlink serial port: " + ec.message());
                }
                receive_({buffer_.data(), n}, false);
                asio::post(port_.get_executor(), [this] { read(); });
            });
    }

    asio::serial_port port_;
    std::array<std::uint8_t, kReadSize> buffer_{};
    Receiver receive_;
};

}  // namespace

std::unique_ptr<Transport> open_transport(asio::io_context& io, const Endpoint& endpoint) {
    if (endpoint.kind == Endpoint::Kind::kSerial) {
        return std::make_unique<SerialTransport>(io, endpoint);
    }
    return std::make_unique<UdpTransport>(io, endpoint);
}

}  // namespace gport::mavlink::bridge
