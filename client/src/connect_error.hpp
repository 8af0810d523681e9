// The message of a failed connect to gportd's socket, with what to do about
// it: permission denied means the user is not in the gport group, anything
// else most likely that gportd is not running.
#pragma once

#include <cerrno>
#include <string>

namespace gport::client::detail {

inline std::string connect_failure(const std::string& path, int error, const std::string& why) {
    const bool denied = error == EACCES || error == EPERM;
    return "cannot connect to " + path + ": " + why +
           (denied ? " (only root and members of the gport group may connect: "
                     "sudo usermod -aG gport $USER, then log in again)"
                   : " (is gportd running?)");
}

}  // namespace gport::client::detail
