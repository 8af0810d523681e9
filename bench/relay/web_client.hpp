// The benchmark's side of gport-web: TCP connections from a chosen loopback
// address (gport-web allows 16 per address), Bearer-authenticated requests,
// a keep-alive connection used blockingly, and /api/live WebSockets.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <memory>
#include <optional>
#include <string>

namespace gport::bench::relay {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = asio::ip::tcp;
using WebSocket = beast::websocket::stream<tcp::socket, false>;  // as gport-web: no deflate

// Where gport-web serves and the tokens of its token file.
struct WebTarget {
    unsigned short port = 0;
    std::string control_token;
    std::string view_token;
    std::string host() const { return "127.0.0.1:" + std::to_string(port); }
};

// The loopback address of peer group `group` (0: 127.0.0.2, 1: 127.0.0.3, ...).
std::string peer_address(int group);

// A connection to gport-web from `from`; blocking reads time out after
// `timeout_s` (0: never).
tcp::socket connect_from(asio::io_context& io, const std::string& from, const WebTarget& web,
                         int timeout_s = 5);

http::request<http::string_body> bearer_request(http::verb verb, const std::string& target,
                                                const WebTarget& web, const std::string& token);

// A WebSocket on /api/live with the handshake done (throws when refused).
std::unique_ptr<WebSocket> open_live(asio::io_context& io, const std::string& from,
                                     const WebTarget& web, const std::string& token);

// One keep-alive HTTP connection used blockingly from one thread; it
// connects again after an error.
class HttpConnection {
  public:
    HttpConnection(const WebTarget& web, std::string token, std::string from = "127.0.0.1");
    // The answer's status, or nullopt after a transport error or timeout.
    std::optional<unsigned> request(http::verb verb, const std::string& target);

  private:
    asio::io_context io_;
    WebTarget web_;
    std::string token_;
    std::string from_;
    std::optional<tcp::socket> socket_;
    beast::flat_buffer buffer_;
};

}  // namespace gport::bench::relay
