#include "live_socket.hpp"

#include <nlohmann/json.hpp>

#include "gport/contract/names.hpp"
#include "gport/version.hpp"
#include "gport/web/limits.hpp"
#include "http_rules.hpp"
#include "json_text.hpp"

namespace gport::web {

namespace beast = boost::beast;
namespace websocket = beast::websocket;
using nlohmann::json;

void LiveSocket::start(Context& context, std::unique_ptr<Registry::Membership> membership,
                       beast::tcp_stream stream, Request request, Role role) {
    auto socket =
        std::make_shared<LiveSocket>(context, std::move(membership), std::move(stream), role);
    socket->membership_->hold(socket);
    socket->accept(std::move(request));
}

LiveSocket::LiveSocket(Context& context, std::unique_ptr<Registry::Membership> membership,
                       beast::tcp_stream stream, Role role)
    : context_(context),
      membership_(std::move(membership)),
      ws_(std::move(stream)),
      rate_(kMaxWsMessagesPerSecond, kMaxWsMessagesPerSecond),
      role_(role) {
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.read_message_max(kMaxWsMessageBytes);
}

LiveSocket::~LiveSocket() {
    if (jogging_) {
        context_.gateway.stop([](std::optional<client::Error>, const std::string&) {});
    }
}

void LiveSocket::accept(Request request) {
    session_ = bearer_of(request) ? std::string() : session_of(request);
    ws_.async_accept(request, [self = shared_from_this()](beast::error_code ec) {
        if (ec) {
            return;
        }
        self->open_ = true;
        self->membership_->listen(true);
        const json hello = {
            {"method", "hello"},
            {"params",
             {{"role", std::string(role_name(self->role_))}, {"version", std::string(kVersion)}}}};
        self->deliver(std::make_shared<const std::string>(json_text(hello)), false);
        if (auto state = self->context_.gateway.state()) {
            self->deliver(state, false);
        }
        self->read();
    });
}

void LiveSocket::deliver(const Message& message, bool attitude) {
    if (!open_) {
        return;
    }
    outbox_.push(message, attitude);
    if (!writing_) {
        write();
    }
}

// One write at a time; a close waits for the write in flight.
void LiveSocket::write() {
    if (close_) {
        const auto code = *close_;
        close_.reset();
        writing_ = nullptr;
        ws_.async_close(code, [self = shared_from_this()](beast::error_code) {});
        return;
    }
    writing_ = open_ ? outbox_.pop() : nullptr;
    if (!writing_) {
        return;
    }
    ws_.text(true);
    ws_.async_write(boost::asio::buffer(*writing_),
                    [self = shared_from_this()](beast::error_code ec, std::size_t) {
                        if (ec) {
                            self->open_ = false;
                            self->writing_ = nullptr;
                            self->close_.reset();
                            return;
                        }
                        self->write();
                    });
}

void LiveSocket::read() {
    ws_.async_read(input_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
        if (ec) {
            self->open_ = false;  // closed, too big (Beast closes with 1009) or timed out
            self->membership_->listen(false);
            return;
        }
        self->on_message();
    });
}

void LiveSocket::on_message() {
    const auto text = beast::buffers_to_string(input_.data());
    input_.consume(input_.size());
    if (!rate_.take(base::TokenBucket::Clock::now())) {
        close_with(websocket::close_code::policy_error);
        return;
    }
    const auto message = json::parse(text, nullptr, false);
    const auto type = message.is_object() ? message.value("type", json()) : json();
    if (role_ != Role::kControl && (type == "jog" || type == "stop")) {
        reply_error("a view login cannot move the gimbal");
    } else if (type == "jog" && session_ended()) {
        // A logout ends a session for good, its open sockets' jogs included
        // (a stop is still taken: stopping is never refused). The reason
        // goes with the close (at most 123 bytes).
        close_with({websocket::close_code::policy_error,
                    "logged out: this page's session has ended; log in again"});
        return;
    } else if (type == "jog") {
        jog(message);
    } else if (type == "stop") {
        stop();
    } else {
        reply_error(R"(expected {"type":"jog","pitch":P,"yaw":Y,"roll":R} or {"type":"stop"})");
    }
    read();
}

bool LiveSocket::session_ended() {
    return !session_.empty() && !context_.sessions.find(session_);
}

void LiveSocket::jog(const json& message) {
    json params = {{"lease_ms", kJogLeaseMs}, {"duration_ms", kJogDurationMs}};
    for (const char* axis : {"pitch", "yaw", "roll"}) {
        const auto value = message.value(axis, json(0));
        if (!value.is_number()) {
            reply_error(std::string("jog: ") + axis + " must be a number (degrees per second)");
            return;
        }
        params[axis] = value;
    }
    jogging_ = true;
    std::weak_ptr<LiveSocket> weak = shared_from_this();
    context_.gateway.jog(json_text(params),
                         [weak](std::optional<client::Error> error, const std::string&) {
                             if (const auto self = weak.lock(); self && error) {
                                 self->reply_error("jog refused: " + error->message());
                             }
                         });
}

void LiveSocket::stop() {
    jogging_ = false;
    std::weak_ptr<LiveSocket> weak = shared_from_this();
    context_.gateway.stop([weak](std::optional<client::Error> error, const std::string&) {
        if (const auto self = weak.lock(); self && error) {
            self->reply_error("stop refused: " + error->message());
        }
    });
}

void LiveSocket::reply_error(const std::string& message) {
    const json error = {{"method", "error"}, {"params", {{"message", message}}}};
    deliver(std::make_shared<const std::string>(json_text(error)), false);
}

void LiveSocket::close() {
    open_ = false;
    membership_->listen(false);
    beast::error_code ignored;
    beast::get_lowest_layer(ws_).socket().close(ignored);
}

void LiveSocket::close_with(websocket::close_reason reason) {
    open_ = false;
    membership_->listen(false);
    close_ = std::move(reason);
    if (!writing_) {
        write();
    }
}

}  // namespace gport::web
