// The real gport-web on the real gportd --simulate, over TCP on loopback (an
// ephemeral port, read from gport-web's "serving" line), with a token file
// holding one control and one view token; and blocking HTTP and WebSocket
// clients on Beast's client side, every read bounded by a receive timeout.
#pragma once

#include <gtest/gtest.h>

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "harness.hpp"

namespace gport::testing {

namespace http = boost::beast::http;
using Headers = std::map<std::string, std::string>;
using HttpResponse = http::response<http::string_body>;
using WebSocket = boost::beast::websocket::stream<boost::asio::ip::tcp::socket, false>;

inline const std::string kControlToken = "control-token-0123456789abcdef";
inline const std::string kViewToken = "view-token-0123456789abcdef";

// Writes a token file with this text and mode.
void write_token_file(const std::string& path, const std::string& text, unsigned mode);

class WebTest : public ::testing::Test {
  protected:
    void SetUp() override;

    // Starts gport-web with these arguments besides --socket, --listen and
    // (unless given) --token-file; true once it prints where it serves.
    bool start_web(std::vector<std::string> extra = {});

    // True once gport-web answers /api/status with gportd's (it is connected).
    bool connected(const std::string& token = kControlToken);

    // One request on a new connection ("Host" is 127.0.0.1:PORT unless given).
    HttpResponse request(http::verb verb, const std::string& target, Headers headers = {},
                         const std::string& body = "");
    // The same from another source address (127.0.0.2, ...: another peer).
    HttpResponse request_from(const std::string& from, http::verb verb, const std::string& target,
                              Headers headers = {}, const std::string& body = "");
    // A connection from `from`, its reads bounded by a 10 s receive timeout.
    boost::asio::ip::tcp::socket open_from(const std::string& from);
    HttpResponse get(const std::string& target, const std::string& token = kControlToken);
    HttpResponse post(const std::string& target, const std::string& body,
                      const std::string& token = kControlToken);
    // Raw bytes on a new connection and whatever comes back until the close.
    std::string raw(const std::string& bytes);

    // A WebSocket to /api/live; throws boost::system::system_error when
    // the upgrade is refused. `rcvbuf`: the socket's receive buffer (0: the
    // system's).
    std::unique_ptr<WebSocket> live(Headers headers, int rcvbuf = 0);
    std::unique_ptr<WebSocket> live_as(const std::string& token = kControlToken, int rcvbuf = 0);
    // The next text message (empty on timeout or close).
    static std::optional<nlohmann::json> next(WebSocket& ws);
    // The next message with this method, within ~10 s.
    static std::optional<nlohmann::json> next_method(WebSocket& ws, const std::string& method);

    std::string host() const { return "127.0.0.1:" + std::to_string(port_); }
    nlohmann::json gportd_status() { return gportd_->call("status").at("result"); }

    TempDir dir_;
    std::unique_ptr<DaemonProcess> daemon_;
    std::unique_ptr<Client> gportd_;
    std::unique_ptr<Process> web_;
    std::string token_file_;
    unsigned short port_ = 0;
};

}  // namespace gport::testing
