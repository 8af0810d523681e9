// What libgport-client accepts from gportd and how long it waits: the
// limits that keep a client alive against a broken or hostile server
// (docs/client-cpp.md, "Limits"). The Python client uses the same figures.
#pragma once

#include <chrono>
#include <cstddef>

namespace gport::client {

// The longest line read from gportd, in bytes, not counting the newline
// (16 MiB, as the Python client's LINE_LIMIT; gportd's longest reply is a
// few KiB). A longer line ends the connection (ErrorCode::kTransport); the
// client stops reading at the limit, so it never holds much more.
inline constexpr std::size_t kLineLimit = 16 * 1024 * 1024;

// The deepest nesting of arrays and objects accepted in a line (gportd's
// replies nest 6 deep). Checked by a linear scan before parsing; a deeper
// line ends the connection (ErrorCode::kTransport).
inline constexpr std::size_t kNestingLimit = 64;

// How long a call waits for its reply unless set otherwise
// (Client::set_call_timeout, AsyncClient::set_call_timeout): ErrorCode::
// kTimeout after it. gportd answers at once except settings requests, which
// wait for the gimbal: requests.timeout_ms x (1 + requests.retries), 0.9 s
// with the defaults, for each of the client's queued ones (at most 4).
inline constexpr std::chrono::milliseconds kDefaultCallTimeout{10000};

// Added to the call timeout for calls with `wait` (angle, center), whose
// reply comes when the motion ends: gportd ends a motion by
// motion.timeout_ms, which it accepts up to 600 s.
inline constexpr std::chrono::milliseconds kWaitAllowance{600000};

// Notifications Client keeps for next_notification() per kind (attitude,
// link, motion), as the Python client's inbox; beyond that the oldest of
// that kind is dropped and counted (Client::dropped_notifications()).
inline constexpr std::size_t kNotificationQueueLimit = 1024;

}  // namespace gport::client
