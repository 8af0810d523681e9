#include "gport/daemon/core/arbiter.hpp"

#include <fmt/format.h>

#include <utility>

namespace gport::daemon {

std::optional<CommandError> Arbiter::check(const ClientInfo& client, Needs needs) const {
    if (auto refused = check_access(client)) {  // 1. access
        return refused;
    }
    if (needs == Needs::kAccess) {
        return std::nullopt;
    }
    return check_control(client);  // 2. control
}

Outcome<Arbiter::Acquired> Arbiter::acquire(const ClientInfo& client,
                                            const std::optional<ClientInfo>& motion_owner) {
    if (auto refused = check(client, Needs::kAccessAndControl)) {
        return std::move(*refused);
    }
    Acquired acquired{client, !holder_.has_value(),
                      motion_owner.has_value() && motion_owner->id != client.id};
    holder_ = client;
    return acquired;
}

Outcome<std::optional<ClientInfo>> Arbiter::release(const ClientInfo& client) {
    if (held_by_other(client)) {
        return CommandError{ErrorCode::kBusy,
                            fmt::format("control is held by another client (pid {}); only it "
                                        "may release it",
                                        holder_->pid)};
    }
    return std::exchange(holder_, std::nullopt);
}

bool Arbiter::client_gone(const ClientInfo& client) {
    if (!holder_ || holder_->id != client.id) {
        return false;
    }
    holder_.reset();
    return true;
}

bool Arbiter::held_by_other(const ClientInfo& client) const {
    return holder_.has_value() && holder_->id != client.id;
}

std::optional<CommandError> Arbiter::check_access(const ClientInfo& client) const {
    if (policy_.may_command(client)) {
        return std::nullopt;
    }
    return CommandError{ErrorCode::kPermission,
                        fmt::format("permission denied: uid {} may only read (status, "
                                    "attitude, attitude_channel, subscribe, unsubscribe, "
                                    "captures, limits)",
                                    client.uid)};
}

std::optional<CommandError> Arbiter::check_control(const ClientInfo& client) const {
    if (!held_by_other(client)) {
        return std::nullopt;
    }
    return CommandError{ErrorCode::kBusy,
                        fmt::format("control is held by another client (pid {})", holder_->pid)};
}

}  // namespace gport::daemon
