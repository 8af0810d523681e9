// User and group names to ids, through NSS (getpwnam_r / getgrnam_r), so the
// config can say "video" instead of a number that differs between machines.
#pragma once

#include <sys/types.h>

#include <string>

#include "gport/config/result.hpp"

namespace gport::config::detail {

// The error names the user (or group) and says whether it does not exist or
// the lookup itself failed.
Result<uid_t> lookup_user(const std::string& name);
Result<gid_t> lookup_group(const std::string& name);

}  // namespace gport::config::detail
