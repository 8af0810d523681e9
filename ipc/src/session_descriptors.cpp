// A session's reply that carries the attitude channel's descriptors (the
// ring and this connection's wake block, once per connection): sent with
// its own sendmsg, SCM_RIGHTS on its first byte, after every line queued
// before it (docs/api.md, "Shared-memory attitude channel").
#include <sys/socket.h>

#include <cerrno>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>

#include "attitude_channel.hpp"
#include "gport/base/descriptors.hpp"
#include "gport/ipc/json_rpc.hpp"
#include "session.hpp"

namespace gport::ipc {
namespace {

using nlohmann::json;

// The reply to send instead when the descriptors could not be sent: the
// attitude_channel result in it that announced them ("descriptors" > 0)
// becomes -32603 with the same id.
std::string unsent_reply(const std::string& line, const std::string& why) {
    json reply = json::parse(line, nullptr, false);
    const json error = {{"code", rpc_error::kInternal},
                        {"message", std::string(detail::kUnavailable) + why}};
    const auto replace = [&error](json& member) {
        if (member.is_object() && member.contains("result") && member["result"].is_object() &&
            member["result"].contains("slots") && member["result"].value("descriptors", 0) > 0) {
            member.erase("result");
            member["error"] = error;
        }
    };
    if (reply.is_array()) {
        for (auto& member : reply) {
            replace(member);
        }
    } else {
        replace(reply);
    }
    return reply.dump() + '\n';
}

bool client_gone(int error) {
    return error == EPIPE || error == ECONNRESET || error == ENOTCONN;
}

}  // namespace

// Sends the front line with its descriptors. True: all of it went out and
// the caller writes on. False: the socket is full (a wait is armed and the
// line stays queued), the rest of the line is being written as a normal
// write, or the client is gone.
bool Session::send_with_descriptors() {
    const Line line = outbox_.front();
    const auto fds = host_.channel_descriptors(state_.info);
    if (fds[0] < 0 || fds[1] < 0) {  // cannot happen: the block lives as long as the session
        outbox_.replace_front(std::make_shared<const std::string>(
            unsent_reply(*line, "its descriptors are gone; ask again")));
        host_.channel_delivered(state_.info, EBADF);
        return true;
    }
    const ssize_t sent = base::send_with_descriptors(
        socket_.native_handle(), line->data(), line->size(), fds, MSG_DONTWAIT | MSG_NOSIGNAL);
    if (sent < 0) {
        const int error = errno;
        if (error == EAGAIN || error == EWOULDBLOCK) {
            wait_writable();
        } else if (client_gone(error)) {
            close();
        } else {  // ETOOMANYREFS, ENOMEM, ENOBUFS...: nothing was sent
            outbox_.replace_front(std::make_shared<const std::string>(unsent_reply(
                *line, std::string("sending its descriptors: ") + std::strerror(error))));
            host_.channel_delivered(state_.info, error);
            return true;
        }
        return false;
    }
    host_.channel_delivered(state_.info, 0);
    outbox_.pop_front();
    if (static_cast<std::size_t>(sent) == line->size()) {
        return true;
    }
    in_flight_.assign(1, line);
    in_flight_bytes_ = line->size();
    buffers_.assign(1, boost::asio::buffer(*line));
    write_rest(static_cast<std::size_t>(sent));
    return false;
}

// The socket is full: the line stays first in the queue and is sent again
// once the client has read enough. Nothing else is written meanwhile.
void Session::wait_writable() {
    advance(SessionEvent::kWaitWritable);
    socket_.async_wait(Socket::wait_write,
                       [self = shared_from_this()](const boost::system::error_code& error) {
                           self->advance(SessionEvent::kWritable);
                           if (self->closed()) {
                               return;
                           }
                           if (error) {
                               self->close();
                               return;
                           }
                           self->flush();
                       });
}

}  // namespace gport::ipc
