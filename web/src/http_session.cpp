#include "http_session.hpp"

#include "gport/web/limits.hpp"
#include "live_socket.hpp"

namespace gport::web {

namespace beast = boost::beast;

HttpSession::HttpSession(Context& context, boost::asio::ip::tcp::socket socket, std::string peer)
    : context_(context),
      membership_(context.registry.join(std::move(peer))),
      stream_(std::move(socket)),
      delay_(context.io) {}

void HttpSession::start() {
    membership_->hold(weak_from_this());
    read();
}

void HttpSession::close() {
    beast::error_code ignored;
    stream_.socket().close(ignored);
    delay_.cancel();
}

void HttpSession::read() {
    parser_.emplace();
    parser_->header_limit(static_cast<std::uint32_t>(kMaxHeaderBytes));
    parser_->body_limit(kMaxBodyBytes);
    stream_.expires_after(membership_->authenticated() ? kHttpIdleTimeout
                                                       : kUnauthenticatedRequestTimeout);
    http::async_read(
        stream_, buffer_, *parser_,
        [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_read(ec); });
}

void HttpSession::on_read(beast::error_code ec) {
    if (ec == http::error::header_limit) {
        refuse(http::status::request_header_fields_too_large, "request header too large");
        return;
    }
    if (ec == http::error::body_limit) {
        refuse(http::status::payload_too_large, "request body too large");
        return;
    }
    if (ec == http::error::end_of_stream || ec) {
        stream_.socket().shutdown(boost::asio::ip::tcp::socket::shutdown_send, ec);
        return;
    }
    route(shared_from_this(), parser_->release());
}

// The answer, then the rest of what the client sends is read and dropped
// for a while (bounded), so that closing does not reset the connection
// before the client has read the answer.
void HttpSession::refuse(http::status status, std::string_view message) {
    Request request;
    request.keep_alive(false);
    auto shared = std::make_shared<Response>(error_response(request, status, message));
    stream_.expires_after(kHttpIdleTimeout);
    http::async_write(stream_, *shared,
                      [self = shared_from_this(), shared](beast::error_code ec, std::size_t) {
                          if (!ec) {
                              self->finish(false);
                              self->drain(kMaxBodyBytes * 4);
                          }
                      });
}

void HttpSession::drain(std::size_t budget) {
    stream_.expires_after(std::chrono::seconds(2));
    buffer_.clear();
    stream_.async_read_some(buffer_.prepare(4096), [self = shared_from_this(), budget](
                                                       beast::error_code ec, std::size_t n) {
        if (!ec && n < budget) {
            self->drain(budget - n);
        }
    });
}

void HttpSession::send(Response response) {
    auto shared = std::make_shared<Response>(std::move(response));
    stream_.expires_after(kHttpIdleTimeout);
    http::async_write(stream_, *shared,
                      [self = shared_from_this(), shared](beast::error_code ec, std::size_t) {
                          self->finish(!ec && shared->keep_alive());
                      });
}

void HttpSession::send_after(Response response, std::chrono::steady_clock::duration delay) {
    delay_.expires_after(delay);
    delay_.async_wait(
        [self = shared_from_this(), response = std::move(response)](beast::error_code ec) mutable {
            if (!ec) {
                self->send(std::move(response));
            }
        });
}

void HttpSession::finish(bool keep_alive) {
    if (keep_alive) {
        read();
        return;
    }
    beast::error_code ignored;
    stream_.socket().shutdown(boost::asio::ip::tcp::socket::shutdown_send, ignored);
}

void HttpSession::upgrade(Request request, Role role) {
    stream_.expires_never();
    LiveSocket::start(context_, std::move(membership_), std::move(stream_), std::move(request),
                      role);
}

}  // namespace gport::web
