// Test support: what an emulator (qemu-user, running the ARM builds on an
// amd64 machine) cannot do, asked of the system itself, so that a test skips
// only where the call really fails, saying why (docs/operations.md,
// "Building for ARM"). On a real Linux kernel these return nothing.
#pragma once

#include <fcntl.h>
#include <grp.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>
#include <string>
#include <system_error>

namespace gport::testing {

// True when process `pid` is an emulator running a foreign binary (binfmt_misc
// starts qemu-<arch>-static, whose own memory and code then count in the
// process's figures, e.g. VmRSS).
inline bool runs_under_emulator(pid_t pid) {
    std::error_code error;
    const auto exe = std::filesystem::read_symlink("/proc/" + std::to_string(pid) + "/exe", error);
    return !error && exe.filename().string().rfind("qemu-", 0) == 0;
}

// Why the pty ioctl TIOCGEXCL (Linux 3.8) cannot be asked here, or nothing.
// qemu-user 7.2 does not implement it: "Function not implemented" (ENOSYS),
// or ENOTTY/EINVAL from an emulator that passes unknown ioctls through.
inline std::optional<std::string> tiocgexcl_missing() {
    const int master = ::posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
    if (master < 0) {
        return std::nullopt;  // not this test's concern: it fails on its own
    }
    int exclusive = 0;
    const int rc = ::ioctl(master, TIOCGEXCL, &exclusive);
    const int error = errno;
    ::close(master);
    if (rc == 0 || (error != ENOSYS && error != ENOTTY && error != EINVAL)) {
        return std::nullopt;
    }
    return std::string("the pty ioctl TIOCGEXCL fails here (") + std::strerror(error) +
           "): an emulator such as qemu-user does not implement it, so a stuck exclusive mode "
           "cannot be seen";
}

// Why SO_PEERGROUPS cannot report a peer's two supplementary groups here, or
// nothing: qemu-user truncates the option to 4 bytes and answers ERANGE for
// ever. Asked in a child (needs root, for setgroups) that takes two groups
// and reads its own through a socketpair.
inline std::optional<std::string> so_peergroups_missing() {
    const pid_t child = ::fork();
    if (child == 0) {  // plain system calls only after fork
        const gid_t two[] = {4242, 4343};
        int pair[2];
        if (::setgroups(2, two) != 0 || ::socketpair(AF_UNIX, SOCK_STREAM, 0, pair) != 0) {
            ::_exit(0);  // cannot ask: not an emulator's doing
        }
        gid_t groups[64];
        socklen_t bytes = sizeof(groups);
        const int rc = ::getsockopt(pair[0], SOL_SOCKET, SO_PEERGROUPS, groups, &bytes);
        ::_exit(rc == 0 ? 0 : 100 + (errno & 0x7f));
    }
    int status = 0;
    if (child < 0 || ::waitpid(child, &status, 0) != child || !WIFEXITED(status) ||
        WEXITSTATUS(status) < 100) {
        return std::nullopt;
    }
    return std::string("SO_PEERGROUPS fails here with two groups (") +
           std::strerror(WEXITSTATUS(status) - 100) +
           "): an emulator such as qemu-user truncates it, so a peer's groups cannot be read";
}

}  // namespace gport::testing
