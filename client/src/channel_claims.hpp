// The file descriptors of attitude_channel replies, for Connection and
// AsyncClient alike: which may be kept, which reply claims them, and the
// connection's mapping once it has one.
//
// gportd attaches the two descriptors of a connection's channel to that
// connection's first attitude_channel result and to no other message. So
// two are kept only while this connection has no mapping yet and at least
// one attitude_channel request still has a caller waiting for its reply;
// any other descriptor is closed as soon as it is received. A request whose
// caller gave up (a timeout, an interruption) no longer counts: when its
// late reply comes, the descriptors it carried are closed.
//
// Internal to the project (not installed).
#pragma once

#include <deque>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>

#include "gport/client/attitude_channel.hpp"
#include "gport/client/export.hpp"

namespace gport::client {

class ChannelMapping;

class GPORT_CLIENT_API ChannelClaims {
  public:
    // An attitude_channel request went out with this id.
    void expect(int id) { waiting_.insert(id); }
    // The caller of request `id` stopped waiting (no-op for other requests).
    void abandon(int id) noexcept;
    // Every waiting caller stopped waiting (gportd refused the connection).
    void abandon_all() noexcept;

    // Where recvmsg puts the descriptors it receives (in arrival order);
    // received() right after.
    std::deque<int>& inbox() noexcept { return fds_; }
    // Closes the received descriptors that nobody may claim.
    void received() noexcept;

    // Looks at a reply nobody waits for: when it answers an abandoned
    // attitude_channel request, closes the descriptors it announced.
    void late(const nlohmann::json& reply) noexcept;
    // The channel an awaited attitude_channel reply gives (see
    // claim_channel); throws Error as it does.
    AttitudeChannel claim(const nlohmann::json& reply);

    // The connection ended: closes every descriptor, forgets the mapping.
    void reset() noexcept;

  private:
    std::deque<int> fds_;
    std::set<int> waiting_;
    std::set<int> abandoned_;
    std::shared_ptr<ChannelMapping> mapping_;
};

}  // namespace gport::client
