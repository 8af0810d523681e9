// The benchmarks' and the soak's read of an attitude_channel reply: one
// line and the descriptors that came with it (base/descriptors.hpp's
// receive_with_descriptors, polled until a deadline). Header-only: bench_e2e
// (park_attack.cpp) and gport_soak (soak_channel.cpp) both use it.
#pragma once

#include <poll.h>

#include <chrono>
#include <deque>
#include <optional>
#include <string>

#include "gport/base/descriptors.hpp"

namespace gport::bench {

// The first line received on `socket` (without its '\n'), the descriptors
// appended to `fds`; nullopt on EOF, an error or no full line within
// `timeout`. Bytes after the line are dropped (one request, one reply).
inline std::optional<std::string> read_reply_with_descriptors(int socket, std::deque<int>& fds,
                                                              std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    std::string text;
    while (text.find('\n') == std::string::npos) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
            deadline - std::chrono::steady_clock::now());
        pollfd p{socket, POLLIN, 0};
        if (left.count() <= 0 || ::poll(&p, 1, static_cast<int>(left.count())) <= 0) {
            return std::nullopt;
        }
        char data[4096];
        const auto n = base::receive_with_descriptors(socket, data, sizeof(data), fds);
        if (n < 0 && (errno == EAGAIN || errno == EINTR)) {
            continue;
        }
        if (n <= 0) {
            return std::nullopt;
        }
        text.append(data, static_cast<std::size_t>(n));
    }
    return text.substr(0, text.find('\n'));
}

}  // namespace gport::bench
