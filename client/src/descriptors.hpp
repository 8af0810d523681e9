// recvmsg with SCM_RIGHTS for the transports (Connection, AsyncClient):
// gportd attaches a file descriptor to `attitude_channel` replies; the
// received ones are kept in arrival order until claimed.
#pragma once

#include <sys/socket.h>
#include <sys/types.h>
#include <sys/uio.h>

#include <cstddef>
#include <cstring>
#include <deque>

namespace gport::client::detail {

// Descriptors accepted per recvmsg (gportd sends one per reply); the kernel
// closes any beyond (MSG_CTRUNC).
inline constexpr std::size_t kMaxDescriptors = 8;

// One recvmsg (MSG_CMSG_CLOEXEC | flags) into `data`; the descriptors that
// came with the bytes are appended to `fds`. Returns recvmsg's result.
inline ssize_t receive(int socket, char* data, std::size_t size, std::deque<int>& fds,
                       int flags = 0) {
    alignas(cmsghdr) char control[CMSG_SPACE(sizeof(int) * kMaxDescriptors)];
    iovec io{data, size};
    msghdr message{};
    message.msg_iov = &io;
    message.msg_iovlen = 1;
    message.msg_control = control;
    message.msg_controllen = sizeof(control);
    const ssize_t n = ::recvmsg(socket, &message, MSG_CMSG_CLOEXEC | flags);
    if (n < 0) {
        return n;
    }
    for (cmsghdr* c = CMSG_FIRSTHDR(&message); c != nullptr; c = CMSG_NXTHDR(&message, c)) {
        if (c->cmsg_level != SOL_SOCKET || c->cmsg_type != SCM_RIGHTS) {
            continue;
        }
        const std::size_t count = (c->cmsg_len - CMSG_LEN(0)) / sizeof(int);
        for (std::size_t i = 0; i < count; ++i) {
            int fd = -1;
            std::memcpy(&fd, CMSG_DATA(c) + i * sizeof(int), sizeof(int));
            fds.push_back(fd);
        }
    }
    return n;
}

}  // namespace gport::client::detail
