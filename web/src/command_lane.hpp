// gport-web's commands to gportd, on a connection of their own (docs/web.md,
// "The stop comes first"): every browser's stop, jog and change goes here,
// never behind a read. Three rules keep a stop on time whatever the
// browsers send:
//   - a stop goes ahead of everything that waits, replaces a waiting jog,
//     and waiting stops are one stop (their handlers all get its answer);
//   - jogs are speeds, the newest wins: a waiting jog is replaced by a newer
//     one (one jog in flight at a time);
//   - the lane spends at most kCommandsPerSecond of gportd's request budget
//     (gportd's socket.max_requests_per_s, 200 by default: it stops reading
//     a connection beyond it), and jogs and other commands leave
//     kStopReserve requests of it for stops: a flood of jogs from every
//     control browser never makes gportd pause this connection, and a stop
//     always finds room.
// Other commands (angle, center, photo, record, settings) wait first in,
// first out, at most kMaxCommandsWaiting of them (beyond: refused at once as
// busy) and kMaxCommandsInFlight at gportd.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "gport/base/token_bucket.hpp"
#include "gport/client/async_client.hpp"

namespace gport::web {

using Reply = client::Handler<std::string>;

class CommandLane {
  public:
    CommandLane(boost::asio::io_context& io, client::AsyncClient& client);

    // Zero speed, ahead of everything waiting.
    void stop(Reply reply);
    // A speed (gportd's `speed` params as JSON text); replaces a waiting jog,
    // whose handler is never called.
    void jog(std::string params, Reply reply);
    // Any other command of a control login, in order.
    void call(std::string method, std::string params, Reply reply);
    // The connection is gone: everything waiting here fails with `error`
    // (what is at gportd gets the client's transport error).
    void fail_all(const client::Error& error);

    std::size_t waiting() const;

  private:
    struct Call {
        std::string method;
        std::string params;
        Reply reply;
    };

    void pump();
    void send_stop();  // every stop waiting, as one
    bool send_jog();
    bool send_other();
    // Takes a token when the budget has more than `keep` left.
    bool spend(double keep);
    void wake_after_refill(double keep);

    boost::asio::io_context& io_;
    client::AsyncClient& client_;
    base::TokenBucket budget_;
    boost::asio::steady_timer refill_;
    bool refill_armed_ = false;
    std::uint64_t refill_generation_ = 0;
    std::vector<Reply> stop_waiting_;
    std::optional<Call> jog_waiting_;
    bool jog_in_flight_ = false;
    std::deque<Call> others_;
    std::size_t others_in_flight_ = 0;
};

// Refuses a request as busy (kTooManyRequests: "gport-web is busy: WHY; try
// again"), posted: never from inside the call that asked.
void refuse_busy(boost::asio::io_context& io, Reply reply, const std::string& why);

}  // namespace gport::web
