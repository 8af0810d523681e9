#include "acceptor.hpp"

#include <boost/asio/write.hpp>

#include "gport/web/limits.hpp"
#include "http_session.hpp"

namespace gport::web {

namespace asio = boost::asio;
using asio::ip::tcp;

Acceptor::Acceptor(Context& context, const tcp::endpoint& endpoint)
    : context_(context), acceptor_(context.io) {
    acceptor_.open(endpoint.protocol());
    acceptor_.set_option(asio::socket_base::reuse_address(true));
    acceptor_.bind(endpoint);
    acceptor_.listen(asio::socket_base::max_listen_connections);
}

void Acceptor::accept() {
    acceptor_.async_accept(
        [self = shared_from_this()](boost::system::error_code ec, tcp::socket socket) {
            if (!ec) {
                if (self->context_.connections >= kMaxConnections) {
                    self->turn_away(std::move(socket));
                } else {
                    std::make_shared<HttpSession>(self->context_, std::move(socket))->start();
                }
            }
            if (ec != asio::error::operation_aborted) {
                self->accept();
            }
        });
}

void Acceptor::turn_away(tcp::socket socket) {
    static const std::string kBody =
        R"({"error":{"code":503,"message":"too many connections: try later"}})";
    static const std::string kBusy =
        "HTTP/1.1 503 Service Unavailable\r\nContent-Type: application/json\r\n"
        "Connection: close\r\nRetry-After: 5\r\nContent-Length: " +
        std::to_string(kBody.size()) + "\r\n\r\n" + kBody;
    auto shared = std::make_shared<tcp::socket>(std::move(socket));
    asio::async_write(*shared, asio::buffer(kBusy),
                      [shared](boost::system::error_code, std::size_t) {
                          boost::system::error_code ignored;
                          shared->shutdown(tcp::socket::shutdown_both, ignored);
                      });
}

}  // namespace gport::web
