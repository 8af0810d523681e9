// gport-web's bounds, one place (docs/web.md, "Limits"): what a browser may
// send, hold open or make the server keep.
#pragma once

#include <chrono>
#include <cstddef>

namespace gport::web {

using namespace std::chrono_literals;

inline constexpr unsigned short kDefaultPort = 8790;

// HTTP: one request's header and body, the connections served at once (of
// them, from one peer address, and not yet authenticated: beyond, a new one
// closes the oldest unauthenticated one), how long an authenticated
// connection may sit between requests or within one, and how long an
// unauthenticated one has for each whole request.
inline constexpr std::size_t kMaxHeaderBytes = 8 * 1024;           // beyond: 431
inline constexpr std::size_t kMaxBodyBytes = 16 * 1024;            // beyond: 413
inline constexpr std::size_t kMaxConnections = 64;                 // beyond: 503
inline constexpr std::size_t kMaxConnectionsPerAddress = 16;       // beyond: 503
inline constexpr std::size_t kMaxUnauthenticatedConnections = 48;  // beyond: oldest closed
inline constexpr auto kHttpIdleTimeout = 30s;
inline constexpr auto kUnauthenticatedRequestTimeout = 5s;

// The live WebSocket: one message from a browser, the messages a browser may
// send a second (beyond: closed with 1008), and the outbound queue of each
// socket: the newest attitude only, plus this many other messages (the
// oldest dropped, counted).
inline constexpr std::size_t kMaxWsMessageBytes = 4 * 1024;
inline constexpr double kMaxWsMessagesPerSecond = 30;
inline constexpr std::size_t kMaxQueuedMessages = 64;

// Sessions and logins: the sessions kept (the oldest ends beyond), how long
// an unused session lives, the failed logins allowed per window from one
// peer address and from all of them together, the addresses remembered
// (the least recently failing forgotten beyond), and how long a wrong token
// beyond those waits for its 429 (Retry-After: until the window has room).
// A valid token or session is never refused by these.
inline constexpr std::size_t kMaxSessions = 256;
inline constexpr auto kSessionIdle = std::chrono::hours(12);
inline constexpr std::size_t kMaxLoginFailures = 5;
inline constexpr std::size_t kMaxLoginFailuresTotal = 60;
inline constexpr std::size_t kMaxLoginAddresses = 1024;
inline constexpr auto kLoginWindow = 60s;
inline constexpr auto kLoginTarpit = 1s;

// API requests from one peer address (the key of registry.hpp: an IPv4
// address, an IPv6 /64), all its logins together, a stop never counted
// (beyond: 429 with Retry-After), for at most this many addresses.
inline constexpr double kApiRequestsPerSecond = 50;
inline constexpr double kApiRequestBurst = 100;
inline constexpr std::size_t kMaxRateAddresses = 1024;

// One-time login codes (login_codes.hpp): how long one works, and how many
// used ones are remembered until they expire (beyond: no new one works
// until some expire; only token holders make codes).
inline constexpr auto kLoginCodeLifetime = std::chrono::minutes(10);
inline constexpr std::size_t kMaxLoginCodesRemembered = 4096;

// gportd: the reconnect period, the status poll for the live sockets, and
// the jog's speed lease and longest motion.
inline constexpr auto kReconnectPeriod = 1s;
inline constexpr auto kStatusPeriod = 1s;
inline constexpr int kJogLeaseMs = 400;
inline constexpr int kJogDurationMs = 10000;
inline constexpr double kAttitudeMaxRateHz = 50;

// gportd's two connections (docs/web.md, "The stop comes first"). The
// commands' one: the requests a second it spends of gportd's budget (its
// socket.max_requests_per_s, 200 by default, must stay above) and its
// burst, the requests of it only a stop may spend, the commands other than
// stops and jogs that may wait (beyond: refused as busy) and be at gportd
// at once. The reads' one: how old a status, limits or settings snapshot
// may be before a browser's request fetches a new one (one fetch for all
// browsers asking meanwhile), and the other reads (capture pages) that may
// be at gportd at once and wait (beyond: refused as busy).
inline constexpr double kCommandsPerSecond = 100;
inline constexpr double kCommandBurst = 20;
inline constexpr double kStopReserve = 5;
inline constexpr std::size_t kMaxCommandsWaiting = 64;
inline constexpr std::size_t kMaxCommandsInFlight = 4;
inline constexpr auto kSnapshotMaxAge = 1s;
inline constexpr std::size_t kMaxReadsInFlight = 8;
inline constexpr std::size_t kMaxReadsWaiting = 128;

// The capture log's downloads: entries asked for per page.
inline constexpr unsigned kCapturesPageSize = 200;

}  // namespace gport::web
