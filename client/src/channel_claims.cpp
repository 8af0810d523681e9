// ChannelClaims: the one place both transports decide which received
// descriptors may be kept and which reply they belong to.
#include "channel_claims.hpp"

#include <unistd.h>

#include <new>
#include <optional>

#include "gport/base/descriptors.hpp"
#include "ring_channel.hpp"

namespace gport::client {
namespace {

std::optional<int> id_of(const nlohmann::json& reply) {
    const auto id = reply.find("id");
    if (id == reply.end() || !id->is_number_integer()) {
        return std::nullopt;
    }
    return id->get<int>();
}

// How many descriptors a reply says it carries: 2 or none.
std::size_t announced(const nlohmann::json& reply) {
    const auto result = reply.find("result");
    if (result == reply.end() || !result->is_object()) {
        return 0;
    }
    const auto count = result->find("descriptors");
    return count != result->end() && *count == 2 ? 2 : 0;
}

}  // namespace

void ChannelClaims::abandon(int id) noexcept {
    if (waiting_.erase(id) > 0) {
        try {
            abandoned_.insert(id);
        } catch (const std::bad_alloc&) {
            // Untracked: its late reply's descriptors are closed at once
            // unless another request waits then (and claim() checks them).
        }
    }
    received();
}

void ChannelClaims::abandon_all() noexcept {
    abandoned_.merge(waiting_);  // moves nodes: allocates nothing
    waiting_.clear();
    received();
}

void ChannelClaims::received() noexcept {
    base::keep_descriptors(fds_, !mapping_ && !waiting_.empty() ? 2 : 0);
}

void ChannelClaims::late(const nlohmann::json& reply) noexcept {
    const auto id = id_of(reply);
    if (!id || abandoned_.erase(*id) == 0) {
        return;
    }
    for (auto n = announced(reply); n > 0 && !fds_.empty(); --n) {
        ::close(base::take_descriptor(fds_));
    }
    received();
}

AttitudeChannel ChannelClaims::claim(const nlohmann::json& reply) {
    if (const auto id = id_of(reply)) {
        waiting_.erase(*id);
    }
    try {
        auto channel = claim_channel(reply, fds_, mapping_);
        received();
        return channel;
    } catch (...) {
        received();
        throw;
    }
}

void ChannelClaims::reset() noexcept {
    base::close_descriptors(fds_);
    waiting_.clear();
    abandoned_.clear();
    mapping_.reset();
}

}  // namespace gport::client
