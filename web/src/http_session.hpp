// One HTTP connection: requests read within the header and body limits
// (431, 413), the timeouts (shorter before a valid session or token), one
// answer at a time (a refused guess's after the tarpit delay), and the
// hand-over of a WebSocket upgrade to a LiveSocket.
#pragma once

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <memory>
#include <optional>

#include "context.hpp"
#include "http_rules.hpp"

namespace gport::web {

class HttpSession : public Member, public std::enable_shared_from_this<HttpSession> {
  public:
    HttpSession(Context& context, boost::asio::ip::tcp::socket socket, std::string peer);
    HttpSession(const HttpSession&) = delete;
    HttpSession& operator=(const HttpSession&) = delete;
    // Reads the first request (held by the registry from now on).
    void start();
    // Member: its socket and timer closed (evicted, or at exit).
    void close() override;
    void deliver(const Message&, bool) override {}  // it never listens

    Context& context() { return context_; }
    boost::beast::tcp_stream& stream() { return stream_; }
    Registry::Membership& membership() { return *membership_; }
    // Writes the answer, then reads the next request (or closes).
    void send(Response response);
    // The same after `delay` (a timer: the loop goes on meanwhile).
    void send_after(Response response, std::chrono::steady_clock::duration delay);
    // After a streamed answer: the next request, or the end.
    void finish(bool keep_alive);
    // Hands the connection to a live WebSocket.
    void upgrade(Request request, Role role);

  private:
    void read();
    void on_read(boost::beast::error_code ec);
    void refuse(http::status status, std::string_view message);
    void drain(std::size_t budget);

    Context& context_;
    std::unique_ptr<Registry::Membership> membership_;
    boost::beast::tcp_stream stream_;
    boost::asio::steady_timer delay_;
    boost::beast::flat_buffer buffer_;
    std::optional<http::request_parser<http::string_body>> parser_;
};

// The answer to one request (routes.cpp).
void route(const std::shared_ptr<HttpSession>& session, Request request);
// The /api/ paths for a logged-in request (api.cpp).
void api(const std::shared_ptr<HttpSession>& session, Request request, Role role);
// /api/captures.csv and .geojson, streamed page by page (downloads.cpp).
void download_captures(const std::shared_ptr<HttpSession>& session, const Request& request,
                       bool geojson);

}  // namespace gport::web
