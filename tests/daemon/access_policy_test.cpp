// Who may command: the peer's own primary and supplementary groups (from
// SO_PEERGROUPS at connect), never the user database's idea of its uid.
#include "gport/daemon/core/access_policy.hpp"

#include <grp.h>
#include <gtest/gtest.h>
#include <pwd.h>

#include <optional>
#include <string>

namespace gport::daemon {
namespace {

config::AccessConfig gids(std::vector<gid_t> list) {
    config::AccessConfig config;
    config.control_gids = std::move(list);
    return config;
}

TEST(AccessPolicy, SupplementaryGroupsOfThePeerCount) {
    AccessPolicy policy(gids({4242}));
    EXPECT_TRUE(policy.may_command({1, 100, 5000, 5000, {7, 4242}}));
    EXPECT_TRUE(policy.may_command({2, 101, 5001, 4242, {}})) << "primary group";
    EXPECT_FALSE(policy.may_command({3, 102, 5002, 5002, {7, 8}}));
}

// A user the database lists in a control group, whose process dropped that
// group (or never had it), may not command.
TEST(AccessPolicy, TheUserDatabaseIsNotAsked) {
    std::optional<std::pair<uid_t, gid_t>> member;  // (a member's uid, the group)
    ::setgrent();
    while (const group* g = ::getgrent()) {
        for (char** name = g->gr_mem; name != nullptr && *name != nullptr && !member; ++name) {
            if (const passwd* pw = ::getpwnam(*name); pw != nullptr && pw->pw_uid != 0 &&
                                                      pw->pw_uid != ::geteuid() &&
                                                      pw->pw_gid != g->gr_gid) {
                member = std::make_pair(pw->pw_uid, g->gr_gid);
            }
        }
    }
    ::endgrent();
    if (!member) {
        GTEST_SKIP() << "no group in the user database lists a member";
    }
    AccessPolicy policy(gids({member->second}));
    EXPECT_FALSE(policy.may_command({1, 100, member->first, 65534, {}}));
}

}  // namespace
}  // namespace gport::daemon
