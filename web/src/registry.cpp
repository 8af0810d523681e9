// The registry of open connections (gport/web/registry.hpp).
#include "gport/web/registry.hpp"

#include <algorithm>
#include <vector>

#include "gport/web/limits.hpp"

namespace gport::web {

std::string peer_key(const boost::asio::ip::address& address) {
    if (address.is_v6() && address.to_v6().is_v4_mapped()) {
        return boost::asio::ip::make_address_v4(boost::asio::ip::v4_mapped, address.to_v6())
            .to_string();
    }
    if (address.is_v4()) {
        return address.to_string();
    }
    auto bytes = address.to_v6().to_bytes();
    std::fill(bytes.begin() + 8, bytes.end(), 0);
    return boost::asio::ip::address_v6(bytes).to_string() + "/64";
}

Admission Registry::admit(const std::string& peer) {
    if (from(peer) >= kMaxConnectionsPerAddress) {
        return Admission::kTooManyFromPeer;
    }
    // The oldest connection not yet logged in makes room when their share
    // is used up, and also when every slot is taken while one of them is
    // there: no one without a token can keep a logged-in browser's new
    // connection (its Stop, its live socket again) out by holding fewer
    // than 48 slots beside them. Its count ends when its operations do.
    if (unauthenticated_ >= kMaxUnauthenticatedConnections ||
        (members_.size() >= kMaxConnections && unauthenticated_ > 0)) {
        evict_oldest_new();
        return Admission::kServe;
    }
    return members_.size() >= kMaxConnections ? Admission::kFull : Admission::kServe;
}

std::unique_ptr<Registry::Membership> Registry::join(std::string peer) {
    const auto id = next_++;
    ++per_address_[peer];
    ++unauthenticated_;
    members_.emplace(id, Entry{peer, {}, Standing::kNew, false});
    return std::unique_ptr<Membership>(new Membership(*this, id, std::move(peer)));
}

std::size_t Registry::from(const std::string& peer) const {
    const auto it = per_address_.find(peer);
    return it == per_address_.end() ? 0 : it->second;
}

void Registry::broadcast(const Message& message, bool attitude) {
    for (const auto& [id, entry] : members_) {
        if (!entry.listens) {
            continue;
        }
        if (const auto member = entry.member.lock()) {
            member->deliver(message, attitude);
        }
    }
}

void Registry::close_all() {
    // Closing may end a member at once (and so change members_): the weak
    // pointers first, then the calls.
    std::vector<std::weak_ptr<Member>> all;
    all.reserve(members_.size());
    for (const auto& [id, entry] : members_) {
        all.push_back(entry.member);
    }
    for (const auto& weak : all) {
        if (const auto member = weak.lock()) {
            member->close();
        }
    }
}

void Registry::leave(std::uint64_t id) {
    const auto it = members_.find(id);
    if (it == members_.end()) {
        return;
    }
    const auto& entry = it->second;
    if (entry.standing == Standing::kNew) {
        --unauthenticated_;
    }
    if (entry.listens) {
        --listening_;
    }
    if (const auto peer = per_address_.find(entry.peer); peer != per_address_.end()) {
        if (--peer->second == 0) {
            per_address_.erase(peer);
        }
    }
    members_.erase(it);
}

void Registry::authenticate(std::uint64_t id) {
    auto& entry = members_.at(id);
    if (entry.standing == Standing::kNew) {
        --unauthenticated_;
    }
    entry.standing = Standing::kTrusted;
}

void Registry::listen(std::uint64_t id, bool on) {
    auto& entry = members_.at(id);
    if (entry.listens != on) {
        entry.listens = on;
        on ? ++listening_ : --listening_;
    }
}

void Registry::evict_oldest_new() {
    const auto oldest = std::find_if(members_.begin(), members_.end(), [](const auto& member) {
        return member.second.standing == Standing::kNew;
    });
    if (oldest == members_.end()) {
        return;
    }
    oldest->second.standing = Standing::kClosing;
    --unauthenticated_;
    if (const auto member = oldest->second.member.lock()) {
        member->close();
    }
}

}  // namespace gport::web
