// The open connections' counts and the eviction of the oldest
// unauthenticated one (context.hpp).
#include "connections.hpp"

#include <algorithm>

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

ConnectionSlot::ConnectionSlot(Context& context, std::string peer)
    : context_(context), peer_(std::move(peer)), id_(context.connections.next++) {
    ++context_.connections.total;
    ++context_.connections.per_address[peer_];
    context_.connections.unauthenticated[id_] = [] {};
}

ConnectionSlot::~ConnectionSlot() {
    auto& connections = context_.connections;
    --connections.total;
    if (const auto it = connections.per_address.find(peer_); it != connections.per_address.end()) {
        if (--it->second == 0) {
            connections.per_address.erase(it);
        }
    }
    connections.unauthenticated.erase(id_);
}

void ConnectionSlot::on_evict(std::function<void()> close) {
    if (const auto it = context_.connections.unauthenticated.find(id_);
        it != context_.connections.unauthenticated.end()) {
        it->second = std::move(close);
    }
}

void ConnectionSlot::authenticate() {
    authenticated_ = true;
    context_.connections.unauthenticated.erase(id_);
}

Admission admit(Context& context, const std::string& peer) {
    auto& connections = context.connections;
    const auto mine = connections.per_address.find(peer);
    if (mine != connections.per_address.end() && mine->second >= kMaxConnectionsPerAddress) {
        return Admission::kTooManyFromPeer;
    }
    if (connections.unauthenticated.size() >= kMaxUnauthenticatedConnections) {
        auto oldest = connections.unauthenticated.begin();
        auto close = std::move(oldest->second);
        connections.unauthenticated.erase(oldest);
        close();  // its count ends when its operations do
        return Admission::kServe;
    }
    return connections.total >= kMaxConnections ? Admission::kFull : Admission::kServe;
}

}  // namespace gport::web
