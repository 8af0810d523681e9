#include "web_client.hpp"

#include <sys/socket.h>
#include <sys/time.h>

#include <boost/beast/core/error.hpp>

namespace gport::bench::relay {

std::string peer_address(int group) {
    return "127.0.0." + std::to_string(2 + group);
}

tcp::socket connect_from(asio::io_context& io, const std::string& from, const WebTarget& web,
                         int timeout_s) {
    tcp::socket socket(io);
    socket.open(tcp::v4());
    socket.bind(tcp::endpoint(asio::ip::make_address(from), 0));
    socket.connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), web.port));
    socket.set_option(tcp::no_delay(true));
    if (timeout_s > 0) {
        timeval tv{timeout_s, 0};
        ::setsockopt(socket.native_handle(), SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    }
    return socket;
}

http::request<http::string_body> bearer_request(http::verb verb, const std::string& target,
                                                const WebTarget& web, const std::string& token) {
    http::request<http::string_body> request(verb, target, 11);
    request.set(http::field::host, web.host());
    request.set(http::field::authorization, "Bearer " + token);
    if (verb == http::verb::post) {
        request.set(http::field::content_type, "application/json");
    }
    request.keep_alive(true);
    request.prepare_payload();
    return request;
}

std::unique_ptr<WebSocket> open_live(asio::io_context& io, const std::string& from,
                                     const WebTarget& web, const std::string& token) {
    auto ws = std::make_unique<WebSocket>(connect_from(io, from, web, 0));
    ws->set_option(
        beast::websocket::stream_base::decorator([token](beast::websocket::request_type& request) {
            request.set(http::field::authorization, "Bearer " + token);
        }));
    ws->handshake(web.host(), "/api/live");
    return ws;
}

HttpConnection::HttpConnection(const WebTarget& web, std::string token, std::string from)
    : web_(web), token_(std::move(token)), from_(std::move(from)) {}

std::optional<unsigned> HttpConnection::request(http::verb verb, const std::string& target) {
    beast::error_code ec;
    if (!socket_) {
        try {
            socket_.emplace(connect_from(io_, from_, web_));
        } catch (const boost::system::system_error&) {
            return std::nullopt;
        }
        buffer_.clear();
    }
    const auto req = bearer_request(verb, target, web_, token_);
    http::write(*socket_, req, ec);
    http::response<http::string_body> response;
    if (!ec) {
        http::read(*socket_, buffer_, response, ec);
    }
    if (ec || !response.keep_alive()) {
        socket_.reset();
    }
    if (ec) {
        return std::nullopt;
    }
    return response.result_int();
}

}  // namespace gport::bench::relay
