#include "socket_file.hpp"

#include <fmt/format.h>
#include <grp.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <system_error>
#include <vector>

#include "gport/ipc/server.hpp"

namespace gport::ipc::detail {
namespace {

[[noreturn]] void throw_socket_failure(const std::string& path, std::string_view what, int error) {
    auto message =
        fmt::format("socket {}: {}: {}", path, what, std::generic_category().message(error));
    if (error == EACCES || error == EPERM) {
        throw SocketAccessError(message);
    }
    throw std::runtime_error(message);
}

// True when something accepts connections on `path`.
bool someone_listens(const std::string& path) {
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    if (path.size() >= sizeof(address.sun_path)) {
        throw std::runtime_error(fmt::format("socket {}: path longer than {} bytes", path,
                                             sizeof(address.sun_path) - 1));
    }
    std::memcpy(address.sun_path, path.c_str(), path.size() + 1);
    const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) {
        throw_socket_failure(path, "cannot create a probe socket", errno);
    }
    const int rc = ::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof(address));
    const int error = errno;
    ::close(fd);
    if (rc == 0) {
        return true;
    }
    if (error == ECONNREFUSED || error == ENOENT) {
        return false;
    }
    throw_socket_failure(path, "cannot tell whether another daemon uses it", error);
}

gid_t group_id(const std::string& group) {
    std::vector<char> buffer(16384);
    struct group entry {};
    struct group* found = nullptr;
    int rc = 0;
    while ((rc = ::getgrnam_r(group.c_str(), &entry, buffer.data(), buffer.size(), &found)) ==
               ERANGE &&
           buffer.size() < (1u << 20)) {
        buffer.resize(buffer.size() * 2);  // a group with very many members
    }
    if (rc != 0) {
        throw std::runtime_error(
            fmt::format("socket group \"{}\": {}", group, std::generic_category().message(rc)));
    }
    if (found == nullptr) {
        throw std::runtime_error(fmt::format("socket group \"{}\" does not exist", group));
    }
    return found->gr_gid;
}

}  // namespace

void clear_stale_socket(const std::string& path) {
    struct stat info {};
    if (::lstat(path.c_str(), &info) != 0) {
        if (errno == ENOENT) {
            return;
        }
        throw_socket_failure(path, "cannot inspect it", errno);
    }
    if (!S_ISSOCK(info.st_mode)) {
        throw std::runtime_error(fmt::format(
            "socket {}: the path exists and is not a socket; refusing to replace it", path));
    }
    if (someone_listens(path)) {
        throw std::runtime_error(fmt::format(
            "socket {}: another daemon is already listening there; stop it first", path));
    }
    if (::unlink(path.c_str()) != 0 && errno != ENOENT) {
        throw_socket_failure(path, "cannot remove the stale socket file", errno);
    }
}

void apply_mode_and_group(const std::string& path, unsigned mode, const std::string& group) {
    if (!group.empty() && ::chown(path.c_str(), static_cast<uid_t>(-1), group_id(group)) != 0) {
        throw_socket_failure(path, fmt::format("cannot give it to group \"{}\"", group), errno);
    }
    if (::chmod(path.c_str(), static_cast<mode_t>(mode)) != 0) {
        throw_socket_failure(path, fmt::format("cannot set mode {:04o}", mode), errno);
    }
}

}  // namespace gport::ipc::detail
