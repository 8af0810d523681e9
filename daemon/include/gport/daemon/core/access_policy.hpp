// Who may command the gimbal (docs/configuration.md, "access", and
// docs/architecture.md, "Decisions where the specification is silent").
// With no control uids or gids configured, every peer that can connect may:
// the socket's mode is the gate. Otherwise a peer may command when its uid
// is listed, or its primary or supplementary groups (the peer process's own,
// from SO_PEERGROUPS) include a listed gid. Root and the daemon's own user
// always may.
#pragma once

#include <sys/types.h>

#include <unordered_map>
#include <vector>

#include "gport/config/config.hpp"
#include "gport/daemon/events.hpp"

namespace gport::daemon {

class AccessPolicy {
  public:
    explicit AccessPolicy(const config::AccessConfig& config);

    bool may_command(const ClientInfo& client) const;
    // Whether the client may publish the vehicle's state: root, the
    // daemon's own user, or a uid in access.vehicle_uids (no groups: the
    // source is one service's user).
    bool may_publish_vehicle(const ClientInfo& client) const;
    const std::vector<uid_t>& vehicle_uids() const { return vehicle_uids_; }
    void forget(const ClientInfo& client) { cache_.erase(client.id); }

  private:
    bool decide(const ClientInfo& client) const;
    bool listed_gid(gid_t gid) const;

    std::vector<uid_t> uids_;
    std::vector<gid_t> gids_;
    std::vector<uid_t> vehicle_uids_;
    uid_t self_;
    mutable std::unordered_map<std::uint64_t, bool> cache_;  // per connection
};

}  // namespace gport::daemon
