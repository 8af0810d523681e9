// gport-web's two connections to gportd (docs/web.md, "The stop comes
// first"): one for the browsers' commands (CommandLane: stops ahead of
// everything, within a budget gportd never pauses), one for the
// subscription and the reads (ReadLane: one shared snapshot of what every
// browser polls). Connects both and reconnects both (every
// kReconnectPeriod) when either breaks, subscribes once (attitude at
// kAttitudeMaxRateHz, link, motion, capture), fans each notification out
// through the registry as one shared string, and polls `status` for the live
// sockets.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <string>

#include "command_lane.hpp"
#include "gport/client/async_client.hpp"
#include "gport/web/registry.hpp"
#include "read_lane.hpp"

namespace gport::web {

class Gateway {
  public:
    Gateway(boost::asio::io_context& io, std::string socket, Registry& registry);

    void start();
    // Closes the connections for good (at exit): no retry, no poll.
    void close();
    bool connected() const { return connected_; }
    // The {"method":"gportd",...} message while gportd is away; else null.
    Message state() const { return connected_ ? nullptr : state_; }

    // Without a connection each handler gets kTransport at once (posted).
    // A stop, ahead of every other request.
    void stop(Reply reply);
    // A speed (gportd's `speed` params as JSON text): the newest wins.
    void jog(std::string params, Reply reply);
    // Any other command of a control login (params: JSON object text).
    void command(const std::string& method, std::string params, Reply reply);
    // status, limits, get_settings: from the shared snapshot.
    void snapshot(const std::string& method, Reply reply);
    // Any other read (capture pages).
    void read(const std::string& method, std::string params, Reply reply);

  private:
    void connect();
    void connect_commands();
    void subscribe();
    bool refused_offline(Reply& reply);
    // reason: for the browsers (no path); detail: for the journal.
    void lost(const std::string& reason, const std::string& detail);
    void retry();
    void poll_status();

    boost::asio::io_context& io_;
    std::string socket_;
    Registry& registry_;            // the live sockets are its listening members
    client::AsyncClient client_;    // the subscription and the reads
    client::AsyncClient commands_;  // the commands only
    CommandLane command_lane_;
    ReadLane read_lane_;
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
