#include "gport/daemon/core/access_policy.hpp"

#include <unistd.h>

#include <algorithm>

namespace gport::daemon {

AccessPolicy::AccessPolicy(const config::AccessConfig& config)
    : uids_(config.control_uids),
      gids_(config.control_gids),
      vehicle_uids_(config.vehicle_uids.value_or(std::vector<uid_t>{})),
      self_(::geteuid()) {}

bool AccessPolicy::may_publish_vehicle(const ClientInfo& client) const {
    return client.uid == 0 || client.uid == self_ ||
           std::find(vehicle_uids_.begin(), vehicle_uids_.end(), client.uid) != vehicle_uids_.end();
}

bool AccessPolicy::may_command(const ClientInfo& client) const {
    auto [it, inserted] = cache_.try_emplace(client.id, false);
    if (inserted) {
        it->second = decide(client);
    }
    return it->second;
}

bool AccessPolicy::listed_gid(gid_t gid) const {
    return std::find(gids_.begin(), gids_.end(), gid) != gids_.end();
}

// Groups are the peer process's own, as the kernel reported them at connect
// (SO_PEERCRED and SO_PEERGROUPS): a process that dropped a group has lost
// it, one given a group by its service manager has it, whatever the user
// database says, and nothing here blocks the loop on NSS.
bool AccessPolicy::decide(const ClientInfo& client) const {
    if (uids_.empty() && gids_.empty()) {
        return true;
    }
    if (client.uid == 0 || client.uid == self_ ||
        std::find(uids_.begin(), uids_.end(), client.uid) != uids_.end()) {
        return true;
    }
    return listed_gid(client.gid) || std::any_of(client.groups.begin(), client.groups.end(),
                                                 [this](gid_t g) { return listed_gid(g); });
}

}  // namespace gport::daemon
