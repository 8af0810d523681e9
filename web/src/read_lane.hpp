// gport-web's reads of gportd, on the connection that carries its
// subscription (docs/web.md, "The stop comes first"). What every browser
// polls (status, limits, settings) is served from one snapshot, fetched
// again when it is older than kSnapshotMaxAge by whichever request comes
// first, and that one fetch answers every browser asking meanwhile: a
// hundred browsers cost gportd what one does. The other reads (capture
// pages, downloads) go in order, kMaxReadsInFlight at a time at gportd and
// kMaxReadsWaiting waiting (beyond: refused as busy), so no burst of them
// makes gportd pause the connection.
#pragma once

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "command_lane.hpp"
#include "gport/client/async_client.hpp"

namespace gport::web {

class ReadLane {
  public:
    using Clock = std::chrono::steady_clock;

    ReadLane(boost::asio::io_context& io, client::AsyncClient& client);

    // A method without params (status, limits, get_settings) from the
    // snapshot, or from one fetch shared by every caller meanwhile.
    void snapshot(const std::string& method, Reply reply);
    // The next snapshot of `method` is fetched again (its value changed).
    void invalidate(const std::string& method);
    // Any other read, in order.
    void call(std::string method, std::string params, Reply reply);
    // The connection is gone: every reply still waiting here fails (those at
    // gportd get the client's transport error), the snapshots are forgotten.
    void fail_all(const client::Error& error);

  private:
    struct Snapshot {
        std::optional<std::string> result;
        Clock::time_point at;
        std::vector<Reply> waiting;  // for the fetch in flight
        bool fetching = false;
    };
    struct Call {
        std::string method;
        std::string params;
        Reply reply;
    };

    void fetch(const std::string& method);
    void pump();

    boost::asio::io_context& io_;
    client::AsyncClient& client_;
    std::map<std::string, Snapshot> snapshots_;
    std::deque<Call> waiting_;
    std::size_t in_flight_ = 0;
};

}  // namespace gport::web
