#include "web_fixture.hpp"

#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/time.h>

#include <boost/asio/connect.hpp>
#include <boost/asio/write.hpp>
#include <boost/beast/core/buffers_to_string.hpp>
#include <fstream>

namespace gport::testing {

namespace asio = boost::asio;
namespace beast = boost::beast;
using asio::ip::tcp;

namespace {

asio::io_context& io() {
    static asio::io_context context;
    return context;
}

void receive_timeout(tcp::socket& socket, int seconds) {
    timeval tv{seconds, 0};
    ::setsockopt(socket.native_handle(), SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv));
}

// A connection from `from` (any 127/8 address is this host); a receive
// buffer of `rcvbuf` bytes when not 0 (a browser that stops reading fills it
// soon).
tcp::socket connect_to(unsigned short port, int rcvbuf = 0, const std::string& from = "127.0.0.1") {
    tcp::socket socket(io());
    socket.open(tcp::v4());
    if (rcvbuf > 0) {
        ::setsockopt(socket.native_handle(), SOL_SOCKET, SO_RCVBUF, &rcvbuf, sizeof(rcvbuf));
    }
    socket.bind(tcp::endpoint(asio::ip::make_address(from), 0));
    socket.connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port));
    receive_timeout(socket, 10);
    return socket;
}

}  // namespace

void write_token_file(const std::string& path, const std::string& text, unsigned mode) {
    std::ofstream(path) << text;
    ::chmod(path.c_str(), mode);
}

void WebTest::SetUp() {
    daemon_ = std::make_unique<DaemonProcess>(dir_, std::vector<std::string>{"--simulate"});
    gportd_ = std::make_unique<Client>(daemon_->socket());
    ASSERT_TRUE(gportd_->connected());
    ASSERT_TRUE(link_up(*gportd_));
    token_file_ = dir_.file("token");
    write_token_file(token_file_, "control:" + kControlToken + "\nview:" + kViewToken + "\n", 0600);
}

bool WebTest::start_web(std::vector<std::string> extra) {
    std::vector<std::string> argv = {GPORT_WEB_PATH, "--socket", daemon_->socket(), "--listen",
                                     "127.0.0.1:0"};
    if (std::find(extra.begin(), extra.end(), "--token-file") == extra.end()) {
        argv.insert(argv.end(), {"--token-file", token_file_});
    }
    argv.insert(argv.end(), extra.begin(), extra.end());
    web_ = std::make_unique<Process>(argv);
    const auto line = web_->wait_line(
        [](const std::string& l) { return l.starts_with("gport-web: serving http://"); });
    if (!line) {
        return false;
    }
    const auto colon = line->rfind(':');
    port_ = static_cast<unsigned short>(std::stoi(line->substr(colon + 1)));
    return port_ != 0;
}

bool WebTest::connected(const std::string& token) {
    return eventually([&] { return get("/api/status", token).result() == http::status::ok; });
}

HttpResponse WebTest::request(http::verb verb, const std::string& target, Headers headers,
                              const std::string& body) {
    return request_from("127.0.0.1", verb, target, std::move(headers), body);
}

tcp::socket WebTest::open_from(const std::string& from) {
    return connect_to(port_, 0, from);
}

HttpResponse WebTest::request_from(const std::string& from, http::verb verb,
                                   const std::string& target, Headers headers,
                                   const std::string& body) {
    auto socket = connect_to(port_, 0, from);
    http::request<http::string_body> request(verb, target, 11);
    request.set(http::field::host, host());
    for (const auto& [name, value] : headers) {
        request.set(name, value);
    }
    request.body() = body;
    request.prepare_payload();
    http::write(socket, request);
    beast::flat_buffer buffer;
    http::response_parser<http::string_body> parser;
    parser.body_limit(64 * 1024 * 1024);
    http::read(socket, buffer, parser);
    return parser.release();
}

HttpResponse WebTest::get(const std::string& target, const std::string& token) {
    return request(http::verb::get, target, {{"Authorization", "Bearer " + token}});
}

HttpResponse WebTest::post(const std::string& target, const std::string& body,
                           const std::string& token) {
    return request(http::verb::post, target,
                   {{"Authorization", "Bearer " + token}, {"Content-Type", "application/json"}},
                   body);
}

std::string WebTest::raw(const std::string& bytes) {
    auto socket = connect_to(port_);
    boost::system::error_code ec;
    asio::write(socket, asio::buffer(bytes), ec);
    std::string reply;
    char chunk[4096];
    for (;;) {
        const auto n = socket.read_some(asio::buffer(chunk), ec);
        if (ec) {
            return reply;
        }
        reply.append(chunk, n);
    }
}

std::unique_ptr<WebSocket> WebTest::live(Headers headers, int rcvbuf) {
    auto ws = std::make_unique<WebSocket>(connect_to(port_, rcvbuf));
    ws->set_option(beast::websocket::stream_base::decorator(
        [headers](beast::websocket::request_type& request) {
            for (const auto& [name, value] : headers) {
                request.set(name, value);
            }
        }));
    const auto given = headers.find("Host");
    ws->handshake(given == headers.end() ? host() : given->second, "/api/live");
    return ws;
}

std::unique_ptr<WebSocket> WebTest::live_as(const std::string& token, int rcvbuf) {
    return live({{"Authorization", "Bearer " + token}, {"Origin", "http://" + host()}}, rcvbuf);
}

std::optional<nlohmann::json> WebTest::next(WebSocket& ws) {
    beast::flat_buffer buffer;
    boost::system::error_code ec;
    ws.read(buffer, ec);
    if (ec) {
        return std::nullopt;
    }
    return nlohmann::json::parse(beast::buffers_to_string(buffer.data()));
}

std::optional<nlohmann::json> WebTest::next_method(WebSocket& ws, const std::string& method) {
    const auto deadline = std::chrono::steady_clock::now() + 10s;
    while (std::chrono::steady_clock::now() < deadline) {
        auto message = next(ws);
        if (!message) {
            return std::nullopt;
        }
        if (message->value("method", "") == method) {
            return message;
        }
    }
    return std::nullopt;
}

}  // namespace gport::testing
