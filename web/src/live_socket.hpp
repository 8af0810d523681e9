// One browser's live WebSocket (/api/live): hello, then the broadcast's messages
// through a bounded Outbox; jog and stop from a control login; at most
// kMaxWsMessagesPerSecond messages a second from the browser (beyond:
// closed with 1008) of at most kMaxWsMessageBytes (beyond: closed by Beast
// with 1009). A socket that was jogging and closes sends gportd `stop`.
#pragma once

#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <optional>

#include "context.hpp"
#include "gport/base/token_bucket.hpp"
#include "http_rules.hpp"

namespace gport::web {

class LiveSocket : public Member, public std::enable_shared_from_this<LiveSocket> {
  public:
    // Takes over the connection's membership (it stays counted as it was).
    static void start(Context& context, std::unique_ptr<Registry::Membership> membership,
                      boost::beast::tcp_stream stream, Request request, Role role);
    LiveSocket(Context& context, std::unique_ptr<Registry::Membership> membership,
               boost::beast::tcp_stream stream, Role role);
    ~LiveSocket() override;

    // Member: queued through the Outbox (the broadcast's messages, once open).
    void deliver(const Message& message, bool attitude) override;
    // Member: the socket closed (at exit).
    void close() override;

  private:
    void accept(Request request);
    void read();
    void on_message();
    void jog(const nlohmann::json& message);  // parsed once, by on_message
    // Opened with a session cookie that a logout (or 12 h unused) has ended.
    bool session_ended();
    void stop();
    void write();
    void reply_error(const std::string& message);
    void close_with(boost::beast::websocket::close_reason reason);

    Context& context_;
    std::unique_ptr<Registry::Membership> membership_;
    // Without permessage-deflate (the template's false): no compression
    // to attack (a small message inflating to a large one) or to pay for.
    boost::beast::websocket::stream<boost::beast::tcp_stream, false> ws_;
    boost::beast::flat_buffer input_;
    Outbox outbox_;
    Message writing_;  // the message being written (kept alive until written)
    base::TokenBucket rate_;
    Role role_;
    std::string session_;  // the cookie's session id; empty for a token
    bool open_ = false;
    bool jogging_ = false;
    std::optional<boost::beast::websocket::close_reason> close_;  // a close to send
};

}  // namespace gport::web
