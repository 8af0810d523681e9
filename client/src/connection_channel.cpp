// Connection's attitude channel: the descriptors of a connection's first
// attitude_channel reply, mapped once and shared by every later request.
#include <utility>

#include "gport/base/descriptors.hpp"
#include "gport/client/connection.hpp"
#include "gport/client/error.hpp"
#include "ring_channel.hpp"

namespace gport::client {

AttitudeChannel Connection::attitude_channel(
    const std::function<void(const nlohmann::json&)>& on_notification) {
    expect_channel();
    const auto reply = call("attitude_channel", nlohmann::json::object(), on_notification);
    if (!reply) {
        throw Error(ErrorCode::kTransport, "the connection to gportd was lost");
    }
    return channel_from(*reply);
}

AttitudeChannel Connection::channel_from(const nlohmann::json& reply) {
    if (channel_requests_ > 0) {
        --channel_requests_;
    }
    try {
        auto channel = claim_channel(reply, descriptors_, channel_);
        base::keep_descriptors(descriptors_, 2 * channel_requests_);
        return channel;
    } catch (...) {
        base::keep_descriptors(descriptors_, 2 * channel_requests_);
        throw;
    }
}

}  // namespace gport::client
