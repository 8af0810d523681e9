#include "acceptor.hpp"

#include <boost/asio/write.hpp>

#include "http_session.hpp"

namespace gport::web {

namespace asio = boost::asio;
using asio::ip::tcp;

tcp::acceptor listen_on(asio::io_context& io, const tcp::endpoint& endpoint) {
    tcp::acceptor acceptor(io);
    acceptor.open(endpoint.protocol());
    acceptor.set_option(asio::socket_base::reuse_address(true));
    acceptor.bind(endpoint);
    acceptor.listen(asio::socket_base::max_listen_connections);
    return acceptor;
}

void Acceptor::accept() {
    acceptor_.async_accept(
        [self = shared_from_this()](boost::system::error_code ec, tcp::socket socket) {
            if (!ec) {
                self->admit(std::move(socket));
            }
            if (ec != asio::error::operation_aborted) {
                self->accept();
            }
        });
}

void Acceptor::admit(tcp::socket socket) {
    boost::system::error_code ec;
    const auto remote = socket.remote_endpoint(ec);
    if (ec) {
        return;  // gone already
    }
    auto peer = peer_key(remote.address());
    switch (context_.registry.admit(peer)) {
        case Admission::kServe:
            std::make_shared<HttpSession>(context_, std::move(socket), std::move(peer))->start();
            break;
        case Admission::kTooManyFromPeer:
            turn_away(std::move(socket), "too many connections from your address: try later");
            break;
        case Admission::kFull:
            turn_away(std::move(socket), "too many connections: try later");
            break;
    }
}

// 503 with Retry-After, and the close.
void Acceptor::turn_away(tcp::socket socket, const std::string& message) {
    const std::string body = R"({"error":{"code":503,"message":")" + message + R"("}})";
    auto busy = std::make_shared<std::string>(
        "HTTP/1.1 503 Service Unavailable\r\nContent-Type: application/json\r\n"
        "Connection: close\r\nRetry-After: 5\r\nContent-Length: " +
        std::to_string(body.size()) + "\r\n\r\n" + body);
    auto shared = std::make_shared<tcp::socket>(std::move(socket));
    asio::async_write(*shared, asio::buffer(*busy),
                      [shared, busy](boost::system::error_code, std::size_t) {
                          boost::system::error_code ignored;
                          shared->shutdown(tcp::socket::shutdown_both, ignored);
                      });
}

}  // namespace gport::web
