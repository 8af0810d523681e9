#include "gport/ipc/server.hpp"

#include <fmt/format.h>
#include <sys/socket.h>
#include <unistd.h>

#include <boost/asio/post.hpp>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "attitude_channel.hpp"
#include "gport/daemon/client_log.hpp"
#include "gport/ipc/event_json.hpp"
#include "gport/ipc/json_rpc.hpp"
#include "session.hpp"
#include "socket_file.hpp"

namespace gport::ipc {
namespace {

namespace asio = boost::asio;
using stream_protocol = asio::local::stream_protocol;

// SO_PEERGROUPS: the peer's supplementary groups at connect(). ERANGE says
// the buffer was short and sets `bytes` to the size needed: retried with that
// (twice at most; the set cannot change after connect, but an emulator may
// answer ERANGE for ever: qemu-user truncates the option to 4 bytes). Returns
// 0, or the errno when the groups cannot be read.
int peer_groups(int fd, std::vector<gid_t>& groups) {
    socklen_t bytes = static_cast<socklen_t>(64 * sizeof(gid_t));
    for (int attempt = 0; attempt < 3; ++attempt) {
        groups.resize(bytes / sizeof(gid_t) + 1);
        bytes = static_cast<socklen_t>(groups.size() * sizeof(gid_t));
        if (::getsockopt(fd, SOL_SOCKET, SO_PEERGROUPS, groups.data(), &bytes) == 0) {
            groups.resize(bytes / sizeof(gid_t));
            return 0;
        }
        if (errno != ERANGE) {
            break;
        }
    }
    const int error = errno;
    groups.clear();
    return error;
}

// SO_PEERCRED: who is on the other end, as the kernel saw it at connect();
// SO_PEERGROUPS: its supplementary groups at that moment. Both come from the
// peer's own credentials, not the user database, so access follows what the
// process really holds (and nothing here can block on NSS). When the groups
// cannot be read the client is still served, judged by its uid and primary
// gid only (`groups_error` says why): that can only refuse it commanding,
// never grant it more (docs/api.md, "Access").
std::optional<daemon::ClientInfo> peer_of(stream_protocol::socket& socket, int& groups_error) {
    const int fd = socket.native_handle();
    ucred credentials{};
    socklen_t size = sizeof(credentials);
    if (::getsockopt(fd, SOL_SOCKET, SO_PEERCRED, &credentials, &size) != 0) {
        return std::nullopt;
    }
    std::vector<gid_t> groups;
    groups_error = peer_groups(fd, groups);
    return daemon::ClientInfo{0, credentials.pid, credentials.uid, credentials.gid,
                              std::move(groups)};
}

}  // namespace

Server::Server(asio::io_context& io, daemon::Api& api, config::SocketConfig config,
               std::shared_ptr<spdlog::logger> log, std::optional<int> listen_fd)
    : io_(io),
      api_(api),
      config_(std::move(config)),
      log_(std::move(log)),
      listen_fd_(listen_fd),
      acceptor_(io),
      dispatcher_(std::make_unique<Dispatcher>(
          api,
          [this] {
              ServerStats stats{clients(), dropped_total_, channel_->readers(), channel_failures_};
              stats.config_file = config_file_;
              return stats;
          })),
      channel_(std::make_unique<detail::AttitudeChannel>()),
      max_clients_(config_.max_clients),
      trim_timer_(io),
      accept_pause_(io) {
    ChannelHost& channel_host = *this;
    dispatcher_->set_channel_host(&channel_host);
    dispatcher_->captures().on_added([this](std::string_view capture) {
        publish_event(&Subscriptions::capture, [&] { return capture_line(capture); });
    });
}

Server::~Server() {
    close();
}

// Walks the sessions; one that closes meanwhile is erased after the walk.
template <typename F>
void Server::for_each_session(F&& visit) {
    ++walking_;
    for (auto& [id, session] : sessions_) {
        if (!session->closed()) {
            visit(*session);
        }
    }
    if (--walking_ == 0) {
        for (auto id : closed_ids_) {
            sessions_.erase(id);
        }
        closed_ids_.clear();
    }
}

void Server::start() {
    if (started_) {
        return;
    }
    if (listen_fd_) {
        acceptor_.assign(stream_protocol(), *listen_fd_);
        log_->info("listening on the socket passed by systemd (fd {})", *listen_fd_);
    } else {
        detail::clear_stale_socket(config_.path);
        boost::system::error_code error;
        acceptor_.open(stream_protocol(), error);
        if (!error) {
            acceptor_.bind(stream_protocol::endpoint(config_.path), error);
        }
        if (error) {
            auto message = fmt::format("socket {}: cannot bind: {}", config_.path, error.message());
            if (error == boost::system::errc::permission_denied ||
                error == boost::system::errc::operation_not_permitted) {
                throw SocketAccessError(message);
            }
            throw std::runtime_error(message);
        }
        created_file_ = true;
        detail::apply_mode_and_group(config_.path, config_.mode, config_.group);
        acceptor_.listen(asio::socket_base::max_listen_connections, error);
        if (error) {
            throw std::runtime_error(
                fmt::format("socket {}: cannot listen: {}", config_.path, error.message()));
        }
        log_->info("listening on {} (mode {:04o}{}{})", config_.path, config_.mode,
                   config_.group.empty() ? "" : ", group ", config_.group);
    }
    fit_descriptor_limit();
    started_ = true;
    api_.set_observer(this);
    accept();
}

void Server::close() {
    if (closed_) {
        return;
    }
    closed_ = true;
    // Before the sockets: readers learn of it from the ring and their word
    // (the waker thread's last round; joined here).
    channel_->close();
    if (started_) {
        api_.set_observer(nullptr);
    }
    boost::system::error_code ignored;
    acceptor_.close(ignored);
    accept_pause_.cancel();
    trim_timer_.cancel();
    for_each_session([](Session& session) { session.close(); });
    if (created_file_) {
        ::unlink(config_.path.c_str());
        created_file_ = false;
    }
}

std::size_t Server::clients() const {
    return sessions_.size() - closed_ids_.size();
}

capture::CaptureLog& Server::captures() {
    return dispatcher_->captures();
}

// ---- accepting ----------------------------------------------------------------------

void Server::accept() {
    acceptor_.async_accept(
        [this](const boost::system::error_code& error, stream_protocol::socket socket) {
            if (closed_ || error == asio::error::operation_aborted) {
                return;
            }
            if (error) {
                on_accept_error(error);
                return;
            }
            on_accept(std::move(socket));
            accept();
        });
}

void Server::on_accept(stream_protocol::socket socket) {
    int groups_error = 0;
    auto info = peer_of(socket, groups_error);
    if (!info) {
        log_->warn("a client's credentials could not be read (SO_PEERCRED); closing it");
        return;
    }
    if (groups_error != 0) {
        if (const auto count = peer_groups_log_.occur()) {
            log_->warn(
                "the supplementary groups of {} client(s) could not be read "
                "(SO_PEERGROUPS: {}; the latest pid {} uid {}): they are judged by "
                "their uid and primary gid only",
                *count, std::strerror(groups_error), info->pid, info->uid);
        }
    }
    info->id = next_id_++;
    bool asked_core = false;
    if (auto why = admission(*info, asked_core)) {
        if (asked_core) {
            api_.client_closed(*info);  // may_command may cache per connection id
        }
        reject(std::move(socket), *why);
        return;
    }
    SessionHost& host = *this;
    auto session = std::make_shared<Session>(std::move(socket), *info, host);
    sessions_.emplace(info->id, session);
    dispatcher_->invalidate_status();  // status counts the clients
    log_->debug("client {} connected: pid {} uid {} gid {}", info->id, info->pid, info->uid,
                info->gid);
    session->start();
}

void Server::session_closed(const Session& session) {
    const auto info = session.info();
    log_->debug("client {} (pid {}) disconnected", info.id, info.pid);
    dispatcher_->invalidate_status();
    channel_->forget(info.id);  // its mappings stay its own; its word is never bumped again
    if (walking_ > 0) {
        closed_ids_.push_back(info.id);
    } else {
        sessions_.erase(info.id);
    }
    // A session can close inside the core's own emit (an overflow while an
    // event is published) or inside a settings callback: calling the core
    // there would re-enter it. Posted, the deadman still runs within a turn.
    asio::post(io_, [&api = api_, info, gone = session.hung_up()] {
        const daemon::ClientLogScope scope(info);  // the deadman's lines name the client
        if (!gone) {
            api.client_gone(info);
        }
        api.client_closed(info);
    });
    ++closed_since_trim_;
    trim_memory();
}

void Server::client_hung_up(const Session& session) {
    const auto& info = session.info();
    const daemon::ClientLogScope scope(info);
    log_->debug("client {} (pid {}) hung up; writing what it is owed", info.id, info.pid);
    api_.client_gone(info);
}

bool Server::holds_control_or_motion(const daemon::ClientInfo& client) const {
    const auto status = api_.status();
    const auto is = [&](const std::optional<daemon::ClientInfo>& who) {
        return who && who->id == client.id;
    };
    return is(status.controller) || (status.motion && is(status.motion->owner));
}

// ---- the attitude channel -------------------------------------------------------------

std::variant<ChannelInfo, std::string> Server::open_attitude_channel(ClientState& client,
                                                                     bool deliver) {
    if (closed_) {
        return std::string("gportd is stopping");
    }
    // A batch carries on after an earlier member closed its session (an
    // event that overflowed the client's queue): session_closed has already
    // forgotten the client, and a block made now would never be freed.
    const auto session = sessions_.find(client.info.id);
    if (session == sessions_.end() || session->second->closed()) {
        return std::string("the connection is closed");
    }
    auto opened = channel_->open_for(client.info.id, deliver);
    if (auto* error = std::get_if<std::string>(&opened)) {
        channel_failed(client.info, *error);
        return *error;
    }
    if (!client.attitude_channel) {
        client.attitude_channel = true;
        dispatcher_->invalidate_status();
    }
    session->second->attach_descriptors(std::get<std::size_t>(opened));
    return ChannelInfo{base::kRingVersion, detail::AttitudeChannel::kSlots,
                       detail::AttitudeChannel::kBytes, channel_->published(),
                       std::get<std::size_t>(opened)};
}

std::size_t Server::attitude_channel_clients() const {
    return channel_->readers();
}

bool Server::attitude_wakes_done() const {
    return channel_->wakes_done();
}

std::array<int, 2> Server::channel_descriptors(const daemon::ClientInfo& client) const {
    return channel_->descriptors(client.id);
}

void Server::channel_delivered(const daemon::ClientInfo& client, int error) {
    channel_->delivered(client.id, error);
    if (error != 0) {
        channel_failed(client, std::string("sending its descriptors: ") + std::strerror(error));
    }
}

// Out of descriptors (EMFILE, ENFILE, ETOOMANYREFS) or memory: the client
// gets -32603 and may ask again; the journal gets the first failure, then a
// summary at most once a minute.
void Server::channel_failed(const daemon::ClientInfo& client, const std::string& why) {
    ++channel_failures_;
    dispatcher_->invalidate_status();
    if (const auto count = channel_failure_log_.occur()) {
        log_->warn(
            "attitude channel unavailable {} time(s) since the last report; the latest: client "
            "{} (pid {}): {}",
            *count, client.id, client.pid, why);
    }
}

// ---- events -------------------------------------------------------------------------

void Server::on_attitude(const daemon::AttitudeSample& sample) {
    channel_->publish(sample);
    channel_->wake();  // at most ChannelWaker::kInline fast wakes here, the rest the waker thread's
    AttitudeLine line;  // built on first use: nothing is encoded when nobody listens
    for_each_session([&](Session& session) {
        if (session.subscriptions().attitude) {
            if (!line) {
                line = attitude_line(sample);
            }
            session.deliver_attitude(line);
        }
    });
}

void Server::on_link(const daemon::LinkEvent& event) {
    dispatcher_->invalidate_status();
    publish_event(&Subscriptions::link, [&] { return link_line(event); });
}

void Server::on_motion(const daemon::MotionEvent& event) {
    dispatcher_->invalidate_status();
    publish_event(&Subscriptions::motion, [&] { return motion_line(event); });
}

// Delivers a link or motion notification to its subscribers, encoding it
// once, on the first subscriber found.
template <typename Build>
void Server::publish_event(bool Subscriptions::*topic, Build build) {
    Line line;
    for_each_session([&](Session& session) {
        if (session.subscriptions().*topic) {
            if (!line) {
                line = build();
            }
            session.deliver_event(line);
        }
    });
}

}  // namespace gport::ipc
