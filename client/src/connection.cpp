#include "connection.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <system_error>
#include <utility>

#include "codec.hpp"
#include "connect_error.hpp"
#include "gport/base/descriptors.hpp"
#include "gport/client/error.hpp"
#include "gport/contract/names.hpp"

namespace gport::client {
namespace {

// Reads and writes wake up this often to look at interrupted().
constexpr int kPollSliceMs = 100;

using Clock = std::chrono::steady_clock;

std::optional<Clock::time_point> deadline_after(std::optional<std::chrono::milliseconds> limit) {
    return limit ? std::optional(Clock::now() + *limit) : std::nullopt;
}

std::optional<std::chrono::milliseconds> time_left(std::optional<Clock::time_point> deadline) {
    if (!deadline) {
        return std::nullopt;
    }
    return std::max(std::chrono::milliseconds(0),
                    std::chrono::ceil<std::chrono::milliseconds>(*deadline - Clock::now()));
}

// One poll's wait: a slice, or less when the deadline is nearer.
int slice_until(std::optional<Clock::time_point> deadline) {
    const auto left = time_left(deadline);
    return left ? static_cast<int>(std::min<long long>(left->count(), kPollSliceMs)) : kPollSliceMs;
}

}  // namespace

Connection Connection::open(const std::string& path) {
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    if (path.empty() || path.size() >= sizeof(address.sun_path)) {
        throw Error(ErrorCode::kTransport,
                    "cannot connect to " + path + ": the path must be 1 to " +
                        std::to_string(sizeof(address.sun_path) - 1) + " bytes");
    }
    std::memcpy(address.sun_path, path.c_str(), path.size() + 1);
    const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) {
        throw Error(ErrorCode::kTransport,
                    std::string("cannot create a socket: ") + std::strerror(errno));
    }
    if (::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) != 0) {
        const int error = errno;
        ::close(fd);
        throw Error(ErrorCode::kTransport,
                    detail::connect_failure(path, error, std::strerror(error)));
    }
    return Connection(fd);
}

Connection::Connection(Connection&& other) noexcept
    : interrupted(std::move(other.interrupted)),
      fd_(std::exchange(other.fd_, -1)),
      next_id_(other.next_id_),
      lines_(std::move(other.lines_)),
      closed_(other.closed_),
      claims_(std::exchange(other.claims_, {})),
      watched_(std::exchange(other.watched_, -1)),
      call_timeout_(other.call_timeout_),
      failure_(std::move(other.failure_)) {}

Connection& Connection::operator=(Connection&& other) noexcept {
    if (this != &other) {
        close();
        interrupted = std::move(other.interrupted);
        fd_ = std::exchange(other.fd_, -1);
        next_id_ = other.next_id_;
        lines_ = std::move(other.lines_);
        closed_ = other.closed_;
        claims_ = std::exchange(other.claims_, {});
        watched_ = std::exchange(other.watched_, -1);
        call_timeout_ = other.call_timeout_;
        failure_ = std::move(other.failure_);
    }
    return *this;
}

Connection::~Connection() {
    close();
}

void Connection::close() noexcept {
    if (fd_ >= 0) {
        ::close(fd_);
        fd_ = -1;
    }
    claims_.reset();
    closed_ = true;
}

void Connection::fail(const std::string& why) {
    failure_ = why;
    lines_.clear();
    close();
}

std::optional<int> Connection::send(const std::string& method, const nlohmann::json& params) {
    return send(method, params, deadline_after(call_timeout_));
}

std::optional<int> Connection::send(const std::string& method, const nlohmann::json& params,
                                    Deadline deadline) {
    if (fd_ < 0) {
        return std::nullopt;
    }
    const int id = next_id_++;
    nlohmann::json request = {{"jsonrpc", "2.0"}, {"id", id}, {"method", method}};
    if (!params.empty()) {
        request["params"] = params;
    }
    if (method == contract::method::kAttitudeChannel) {
        claims_.expect(id);  // two descriptors may come with its reply
    }
    if (!write_all(request.dump() + "\n", deadline)) {
        if (!closed_ && deadline && std::chrono::steady_clock::now() >= *deadline) {
            fail("gportd did not read the request to " + method +
                 " within the client's call timeout; the connection is closed");
        } else if (!closed_) {
            close();  // interrupted with part of a line sent: the stream is unusable
        }
        return std::nullopt;
    }
    return id;
}

// Without blocking past the deadline or an interruption: a server that does
// not read cannot hold the caller.
bool Connection::write_all(std::string_view left, Deadline deadline) {
    while (!left.empty()) {
        const auto n = ::send(fd_, left.data(), left.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
        if (n > 0) {
            left.remove_prefix(static_cast<std::size_t>(n));
            continue;
        }
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK)) {
            closed_ = true;
            return false;
        }
        if (interrupted() || (deadline && std::chrono::steady_clock::now() >= *deadline)) {
            return false;
        }
        pollfd p{fd_, POLLOUT, 0};
        ::poll(&p, 1, slice_until(deadline));
    }
    return true;
}

bool Connection::fill(Deadline deadline) {
    pollfd p[2] = {{fd_, POLLIN, 0}, {watched_, POLLIN, 0}};
    if (::poll(p, watched_ >= 0 ? 2 : 1, slice_until(deadline)) <= 0) {
        return true;  // nothing yet (or EINTR): the caller checks the clock and signals
    }
    if ((p[0].revents & (POLLIN | POLLHUP | POLLERR)) != 0) {
        receive();
    }
    return (p[1].revents & POLLIN) == 0;
}

// One recvmsg: the bytes go to the buffer, the descriptors to the FIFO.
void Connection::receive() {
    char chunk[65536];
    const auto n = base::receive_with_descriptors(fd_, chunk, sizeof(chunk), claims_.inbox());
    claims_.received();  // none nobody asked for
    if (n < 0 && errno == EINTR) {
        return;
    }
    if (n <= 0) {
        closed_ = true;
        return;
    }
    lines_.append(chunk, static_cast<std::size_t>(n));
}

Connection::ReadStatus Connection::read(nlohmann::json& message,
                                        std::optional<std::chrono::milliseconds> timeout) {
    std::optional<std::chrono::steady_clock::time_point> deadline;
    if (timeout) {
        deadline = std::chrono::steady_clock::now() + *timeout;
    }
    bool polled = false;  // a zero timeout still looks at the socket once
    while (true) {
        try {
            if (const auto line = lines_.next()) {
                if (detail::blank(*line)) {
                    continue;
                }
                message = detail::parse_line(*line);
                claims_.late(message);  // a reply whose caller gave up: its descriptors closed
                return ReadStatus::kMessage;
            }
        } catch (const Error& e) {  // over a limit, not JSON: gportd is broken or hostile
            fail(e.message());
            return ReadStatus::kClosed;
        }
        if (closed_) {
            return ReadStatus::kClosed;
        }
        if (interrupted()) {
            return ReadStatus::kInterrupted;
        }
        if (polled && deadline && std::chrono::steady_clock::now() >= *deadline) {
            return ReadStatus::kTimeout;
        }
        if (!fill(deadline)) {
            return ReadStatus::kWoken;
        }
        polled = true;
    }
}

std::optional<nlohmann::json> Connection::call(
    const std::string& method, const nlohmann::json& params,
    const std::function<void(const nlohmann::json&)>& on_notification) {
    const auto limit = codec::reply_limit(params, call_timeout_);
    const auto deadline = deadline_after(limit);
    const auto id = send(method, params, deadline);
    if (!id) {
        return std::nullopt;
    }
    return await_reply(*id, method, limit, deadline, on_notification);
}

std::optional<nlohmann::json> Connection::await_reply(
    int id, const std::string& method, std::optional<std::chrono::milliseconds> limit,
    Deadline deadline, const std::function<void(const nlohmann::json&)>& on_notification) {
    // The watched descriptor is for the caller's own reads: not polled here
    // (it would stay readable until the caller drains it).
    struct Unwatch {
        Connection& c;
        int watched = std::exchange(c.watched_, -1);
        ~Unwatch() { c.watched_ = watched; }
    } unwatch{*this};
    // Whatever ends the wait but the reply itself: an attitude_channel
    // request no longer awaited (its late reply's descriptors are closed).
    struct Abandon {
        Connection& c;
        int id;
        bool answered = false;
        ~Abandon() {
            if (!answered) {
                c.claims_.abandon(id);
            }
        }
    } abandon{*this, id};
    nlohmann::json message;
    while (true) {
        const auto status = read(message, time_left(deadline));
        if (status == ReadStatus::kTimeout) {
            throw codec::no_reply(method, *limit);
        }
        if (status != ReadStatus::kMessage) {
            return std::nullopt;
        }
        if (message.contains("id")) {
            if (message["id"] == id) {
                abandon.answered = true;
                return message;
            }
            if (message["id"].is_null()) {
                return message;  // the daemon refused us (e.g. too many clients)
            }
        } else if (on_notification) {
            on_notification(message);
        }
        // read() gives every complete line at once, without looking at the
        // clock: a server that keeps the socket full would otherwise hold
        // the call for as long as it floods.
        if (deadline && Clock::now() >= *deadline) {
            throw codec::no_reply(method, *limit);
        }
        if (interrupted()) {
            return std::nullopt;
        }
    }
}

}  // namespace gport::client
