#include "accounts.hpp"

#include <fmt/format.h>
#include <grp.h>
#include <pwd.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <vector>

#include "checks.hpp"

namespace gport::config::detail {
namespace {

// The *_r lookups need a caller-sized buffer; grow it on ERANGE up to a cap
// (a group with thousands of members needs more than the usual hint).
constexpr std::size_t kInitialBuffer = 16 * 1024;
constexpr std::size_t kMaxBuffer = 4 * 1024 * 1024;

// Calls `get(buffer, size)` with a growing buffer; returns its error number.
template <typename Get>
int with_buffer(Get get) {
    std::vector<char> buffer(kInitialBuffer);
    for (;;) {
        const int rc = get(buffer.data(), buffer.size());
        if (rc != ERANGE || buffer.size() >= kMaxBuffer) {
            return rc;
        }
        buffer.resize(buffer.size() * 2);
    }
}

template <typename Id>
Result<Id> lookup_result(int rc, bool found, Id id, std::string_view kind,
                         const std::string& name) {
    if (found) {
        return id;
    }
    // ENOENT, ESRCH, EBADF and EPERM all mean "no such entry" in glibc's and
    // POSIX's wording; anything else is a failed lookup worth reporting.
    if (rc == 0 || rc == ENOENT || rc == ESRCH || rc == EBADF || rc == EPERM) {
        return Errors{{fmt::format("unknown {} {}", kind, json_quoted(name))}};
    }
    return Errors{
        {fmt::format("cannot look up {} {}: {}", kind, json_quoted(name), std::strerror(rc))}};
}

}  // namespace

Result<uid_t> lookup_user(const std::string& name) {
    uid_t uid = 0;
    bool found = false;
    const int rc = with_buffer([&](char* buffer, std::size_t size) {
        passwd entry{};
        passwd* match = nullptr;
        const int r = getpwnam_r(name.c_str(), &entry, buffer, size, &match);
        found = match != nullptr;
        if (found) {
            uid = match->pw_uid;
        }
        return r;
    });
    return lookup_result(rc, found, uid, "user", name);
}

Result<gid_t> lookup_group(const std::string& name) {
    gid_t gid = 0;
    bool found = false;
    const int rc = with_buffer([&](char* buffer, std::size_t size) {
        group entry{};
        group* match = nullptr;
        const int r = getgrnam_r(name.c_str(), &entry, buffer, size, &match);
        found = match != nullptr;
        if (found) {
            gid = match->gr_gid;
        }
        return r;
    });
    return lookup_result(rc, found, gid, "group", name);
}

}  // namespace gport::config::detail
