// The logged-in browsers: server-side sessions under random ids (the
// cookie's value; only its SHA-256 is kept), at most kMaxSessions (the
// least recently used ends beyond), each ending after kSessionIdle unused,
// kept in a file across restarts when asked (persist); and the failed logins,
// at most kMaxLoginFailures per kLoginWindow from one peer address and
// kMaxLoginFailuresTotal from all, for at most kMaxLoginAddresses addresses
// (the least recently failing one forgotten beyond).
#pragma once

#include <chrono>
#include <cstddef>
#include <deque>
#include <list>
#include <map>
#include <optional>
#include <string>

#include "gport/web/tokens.hpp"

namespace gport::web {

class Sessions {
  public:
    using Clock = std::chrono::steady_clock;

    // A new session's id (32 random bytes, hex).
    std::string open(Role role, Clock::time_point now = Clock::now());
    // The session's role, refreshing its use; empty when unknown or expired.
    std::optional<Role> find(const std::string& id, Clock::time_point now = Clock::now());
    void close(const std::string& id);
    std::size_t size() const { return sessions_.size(); }

    // From now on the sessions live in `path` too: read now (those unused
    // for kSessionIdle dropped), written at every login and logout and by
    // save(). The problem when the file cannot be read or trusted (the
    // sessions then start empty and the file is replaced), else "".
    std::string persist(const std::string& path);
    // Writes the file (with the times of last use); the problem, or "".
    std::string save() const;

  private:
    struct Session {
        Role role;
        Clock::time_point used;
    };
    std::map<std::string, Session> sessions_;  // by the SHA-256 of the id
    std::string path_;
};

class LoginGuard {
  public:
    using Clock = std::chrono::steady_clock;

    // While `address` (or all addresses together) has used up the window's
    // failures: the seconds until there is room again.
    std::optional<int> blocked(const std::string& address, Clock::time_point now = Clock::now());
    // Counts a wrong token from `address`.
    void failed(const std::string& address, Clock::time_point now = Clock::now());
    // The addresses remembered (at most kMaxLoginAddresses).
    std::size_t addresses() const { return addresses_.size(); }

  private:
    struct Failures {
        std::deque<Clock::time_point> times;
        std::list<std::string>::iterator order;
    };
    Failures& entry(const std::string& address);
    std::map<std::string, Failures> addresses_;
    std::list<std::string> order_;  // least recently failing first
    std::deque<Clock::time_point> all_;
};

}  // namespace gport::web
