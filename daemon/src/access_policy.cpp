#include "access_policy.hpp"

#include <grp.h>
#include <pwd.h>
#include <unistd.h>

#include <algorithm>

namespace gport::daemon {

AccessPolicy::AccessPolicy(const config::AccessConfig& config)
    : uids_(config.control_uids), gids_(config.control_gids), self_(::geteuid()) {}

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

bool AccessPolicy::decide(const ClientInfo& client) const {
    if (uids_.empty() && gids_.empty()) {
        return true;
    }
    if (client.uid == 0 || client.uid == self_ ||
        std::find(uids_.begin(), uids_.end(), client.uid) != uids_.end() ||
        listed_gid(client.gid)) {
        return true;
    }
    if (gids_.empty()) {
        return false;
    }
    // Supplementary groups are not in SO_PEERCRED; ask the user database.
    std::vector<char> buf(16384);
    passwd pw{};
    passwd* found = nullptr;
    if (::getpwuid_r(client.uid, &pw, buf.data(), buf.size(), &found) != 0 || found == nullptr) {
        return false;
    }
    int count = 64;
    std::vector<gid_t> groups(static_cast<std::size_t>(count));
    if (::getgrouplist(pw.pw_name, client.gid, groups.data(), &count) < 0) {
        groups.resize(static_cast<std::size_t>(count));
        ::getgrouplist(pw.pw_name, client.gid, groups.data(), &count);
    }
    groups.resize(static_cast<std::size_t>(std::max(count, 0)));
    return std::any_of(groups.begin(), groups.end(), [this](gid_t g) { return listed_gid(g); });
}

}  // namespace gport::daemon
