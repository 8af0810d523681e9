// Control arbitration: who may command (AccessPolicy) and who holds control
// (the client that acquired it, if any). Every command is checked here, in
// one fixed order, before the core looks at the device:
//
//   1. access   (kPermission) — a peer that may only read is refused;
//   2. control  (kBusy)       — another client holds control.
//
// stop needs only the first (stopping is always safe, whoever holds
// control); release needs only the second (anyone may release what nobody
// else holds). The decisions that go with control — whether an acquire
// preempts a running motion, whether a client's departure frees control —
// are made here too; the core carries them out and logs them.
#pragma once

#include <optional>
#include <utility>

#include "gport/daemon/core/access_policy.hpp"
#include "gport/daemon/events.hpp"
#include "gport/daemon/outcome.hpp"

namespace gport::daemon {

class Arbiter {
  public:
    // Which of the checks a request must pass (see above).
    enum class Needs {
        kAccess,            // stop
        kAccessAndControl,  // every other command and settings request
    };

    struct Acquired {
        ClientInfo holder;
        bool newly_held = false;  // nobody held control before
        bool preempts = false;    // another client's motion must end (kPreempted)
    };

    explicit Arbiter(AccessPolicy policy) : policy_(std::move(policy)) {}

    // Reload: a fresh policy, so no cached decision survives. Control stays
    // with its holder.
    void set_policy(AccessPolicy policy) { policy_ = std::move(policy); }

    bool may_command(const ClientInfo& client) const { return policy_.may_command(client); }
    const AccessPolicy& policy() const { return policy_; }
    const std::optional<ClientInfo>& holder() const { return holder_; }

    // The checks, in the order above; the first that fails is the answer.
    std::optional<CommandError> check(const ClientInfo& client, Needs needs) const;

    // Access, then control; then the client holds control. motion_owner is
    // the owner of the running speed motion, if any: another client's motion
    // is preempted. The holder is recorded before the caller ends it.
    Outcome<Acquired> acquire(const ClientInfo& client,
                              const std::optional<ClientInfo>& motion_owner);
    // Control only (no access check): nobody holds control afterwards. The
    // value is the holder released, empty when nobody held control.
    Outcome<std::optional<ClientInfo>> release(const ClientInfo& client);

    // The client's connection went away: true when it held control (now free).
    bool client_gone(const ClientInfo& client);
    // The connection is closed for good: its cached access decision goes.
    void forget(const ClientInfo& client) { policy_.forget(client); }

  private:
    bool held_by_other(const ClientInfo& client) const;
    std::optional<CommandError> check_access(const ClientInfo& client) const;
    std::optional<CommandError> check_control(const ClientInfo& client) const;

    AccessPolicy policy_;
    std::optional<ClientInfo> holder_;
};

}  // namespace gport::daemon
