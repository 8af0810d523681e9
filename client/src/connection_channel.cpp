// Connection's attitude channel: the descriptors of a connection's first
// attitude_channel reply, mapped once and shared by every later request
// (ChannelClaims).
#include "connection.hpp"
#include "gport/client/error.hpp"
#include "gport/contract/names.hpp"

namespace gport::client {

AttitudeChannel Connection::attitude_channel(
    const std::function<void(const nlohmann::json&)>& on_notification) {
    const auto reply =
        call(contract::method::kAttitudeChannel, nlohmann::json::object(), on_notification);
    if (!reply) {
        throw Error(ErrorCode::kTransport, "the connection to gportd was lost");
    }
    return channel_from(*reply);
}

}  // namespace gport::client
