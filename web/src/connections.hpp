// Who may connect (docs/web.md, "Limits"): at most kMaxConnections, at most
// kMaxConnectionsPerAddress from one peer, and at most
// kMaxUnauthenticatedConnections that have not yet shown a valid session or
// token; beyond that a new connection takes the room of the oldest
// unauthenticated one (which is closed), so that idle or slow peers cannot
// hold the slots the operator's page needs.
#pragma once

#include <string>

#include "context.hpp"

namespace gport::web {

enum class Admission { kServe, kTooManyFromPeer, kFull };

// Whether a new connection from `peer` (peer_key) is served; may close the
// oldest unauthenticated connection to make room.
Admission admit(Context& context, const std::string& peer);

}  // namespace gport::web
