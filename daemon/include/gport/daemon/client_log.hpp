// The journal fields that name a client: GPORT_CLIENT_PID, GPORT_CLIENT_UID
// and GPORT_CLIENT_ID, on every line logged while a ClientLogScope is alive.
// ipc scopes a client's request and its settings replies; the core scopes
// its lines about a motion with the motion's owner (docs/operations.md,
// "Logs").
#pragma once

#include <array>
#include <optional>
#include <span>

#include "gport/base/log_context.hpp"
#include "gport/daemon/events.hpp"

namespace gport::daemon {

class ClientLogScope {
  public:
    explicit ClientLogScope(const ClientInfo& client)
        : fields_(base::process_log_context(), fields_of(client)) {}
    // No client (a motion without an owner): adds nothing.
    explicit ClientLogScope(const std::optional<ClientInfo>& client)
        : fields_(base::process_log_context(),
                  client ? std::span<const base::LogField>(fields_of(*client))
                         : std::span<const base::LogField>()) {}

    ClientLogScope(const ClientLogScope&) = delete;
    ClientLogScope& operator=(const ClientLogScope&) = delete;

  private:
    static std::array<base::LogField, 3> fields_of(const ClientInfo& client) {
        return {base::LogField(base::kFieldClientPid, client.pid),
                base::LogField(base::kFieldClientUid, client.uid),
                base::LogField(base::kFieldClientId, client.id)};
    }

    base::LogFields fields_;
};

}  // namespace gport::daemon
