// JSON encoding of method results (the event side is in event_json; the
// pieces both use are in json_common).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "gport/ipc/json_rpc.hpp"

namespace gport::ipc::detail {

// The status result without its `client` member: the same for every caller.
nlohmann::json shared_status_json(const daemon::Status& status, const ServerStats& stats);
// The status result's `client` member: the caller's own.
nlohmann::json client_status_json(const ClientState& client);
nlohmann::json controller_json(const std::optional<daemon::ClientInfo>& holder,
                               const daemon::ClientInfo& caller);
nlohmann::json settings_json(const daemon::Settings& settings);
nlohmann::json subscriptions_json(const Subscriptions& subscriptions);

}  // namespace gport::ipc::detail
