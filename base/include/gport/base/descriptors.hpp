// sendmsg and recvmsg with SCM_RIGHTS: gportd attaches the attitude channel's two
// descriptors (the ring and the connection's wake block) to the first
// `attitude_channel` reply of a connection (docs/api.md). The client
// library's transports, the benchmarks and the tests read the socket with it
// and keep the descriptors received in arrival order until claimed; a
// client keeps no more than it asked for (keep_descriptors).
#pragma once

#include <sys/socket.h>
#include <sys/types.h>
#include <sys/uio.h>
#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <cstring>
#include <deque>
#include <span>

namespace gport::base {

// Descriptors accepted per recvmsg: gportd sends at most two per line (and
// a Unix stream socket never hands over two lines' descriptors in one read);
// the room for more only lets a client see, and close, what a hostile peer
// sent. The kernel closes any beyond (MSG_CTRUNC).
inline constexpr std::size_t kMaxDescriptors = 32;

// One recvmsg (MSG_CMSG_CLOEXEC | flags) into `data`; the descriptors that
// came with the bytes are appended to `fds`. Returns recvmsg's result.
inline ssize_t receive_with_descriptors(int socket, char* data, std::size_t size,
                                        std::deque<int>& fds, int flags = 0) {
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

// Descriptors one sendmsg may carry (Linux's SCM_MAX_FD).
inline constexpr std::size_t kMaxSendDescriptors = 253;

// One sendmsg of `size` bytes of `data` with `fds` attached (SCM_RIGHTS; no
// control message when `fds` is empty), retried on EINTR. Returns sendmsg's
// result; more than kMaxSendDescriptors is -1 with EINVAL. No allocation:
// safe in a child after fork.
inline ssize_t send_with_descriptors(int socket, const char* data, std::size_t size,
                                     std::span<const int> fds, int flags = MSG_NOSIGNAL) {
    if (fds.size() > kMaxSendDescriptors) {
        errno = EINVAL;
        return -1;
    }
    alignas(cmsghdr) char control[CMSG_SPACE(sizeof(int) * kMaxSendDescriptors)]{};
    iovec io{const_cast<char*>(data), size};
    msghdr message{};
    message.msg_iov = &io;
    message.msg_iovlen = 1;
    if (!fds.empty()) {
        message.msg_control = control;
        message.msg_controllen = CMSG_SPACE(sizeof(int) * fds.size());
        cmsghdr* header = CMSG_FIRSTHDR(&message);
        header->cmsg_level = SOL_SOCKET;
        header->cmsg_type = SCM_RIGHTS;
        header->cmsg_len = CMSG_LEN(sizeof(int) * fds.size());
        std::memcpy(CMSG_DATA(header), fds.data(), sizeof(int) * fds.size());
    }
    ssize_t sent = -1;
    do {
        sent = ::sendmsg(socket, &message, flags);
    } while (sent < 0 && errno == EINTR);
    return sent;
}

// The first descriptor received and not claimed yet, or -1; the caller
// owns it.
inline int take_descriptor(std::deque<int>& fds) noexcept {
    if (fds.empty()) {
        return -1;
    }
    const int fd = fds.front();
    fds.pop_front();
    return fd;
}

// Closes the newest descriptors beyond the first `keep` (the ones nobody
// asked for: a client keeps at most two per attitude_channel request
// awaiting its reply). Returns how many it closed.
inline std::size_t keep_descriptors(std::deque<int>& fds, std::size_t keep) noexcept {
    std::size_t closed = 0;
    while (fds.size() > keep) {
        ::close(fds.back());
        fds.pop_back();
        ++closed;
    }
    return closed;
}

// Closes every descriptor nobody claimed.
inline void close_descriptors(std::deque<int>& fds) noexcept {
    for (const int fd : fds) {
        ::close(fd);
    }
    fds.clear();
}

}  // namespace gport::base
