// gport-web's one connection to gportd: connects and reconnects (every
// kReconnectPeriod), subscribes once (attitude at kAttitudeMaxRateHz, link,
// motion, capture), fans each notification out through the hub as one
// shared string, polls `status` for the live sockets, and passes the HTTP
// API's and the jog's calls on.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <string>

#include "gport/client/async_client.hpp"
#include "hub.hpp"

namespace gport::web {

class Gateway {
  public:
    Gateway(boost::asio::io_context& io, std::string socket, Hub& hub);

    void start();
    // Closes the connection for good (at exit): no retry, no poll.
    void stop();
    bool connected() const { return connected_; }
    // The {"method":"gportd",...} message while gportd is away; else null.
    Message state() const { return connected_ ? nullptr : state_; }

    // A call of any gportd method (params: JSON object text); without a
    // connection the handler gets kTransport at once (posted).
    void call(const std::string& method, const std::string& params,
              client::Handler<std::string> handler);

  private:
    void connect();
    void subscribe();
    // reason: for the browsers (no path); detail: for the journal.
    void lost(const std::string& reason, const std::string& detail);
    void retry();
    void poll_status();

    boost::asio::io_context& io_;
    std::string socket_;
    Hub& hub_;
    client::AsyncClient client_;
    boost::asio::steady_timer reconnect_;
    boost::asio::steady_timer status_;
    bool connected_ = false;
    bool stopped_ = false;
    bool announced_down_ = false;
    Message state_;
};

// `{"method":"gportd","params":{"connected":C,"reason":R}}`.
Message gportd_message(bool connected, const std::string& reason);

}  // namespace gport::web
