// The logged-in browsers: server-side sessions under random ids (the
// cookie's value), at most kMaxSessions (the least recently used ends
// beyond), each ending after kSessionIdle unused; and the failed logins,
// at most kMaxLoginFailures per kLoginWindow.
#pragma once

#include <chrono>
#include <deque>
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

  private:
    struct Session {
        Role role;
        Clock::time_point used;
    };
    std::map<std::string, Session> sessions_;
};

class LoginGuard {
  public:
    using Clock = std::chrono::steady_clock;

    // While the window's failures are used up: the seconds until it ends.
    std::optional<int> blocked(Clock::time_point now = Clock::now());
    void failed(Clock::time_point now = Clock::now());

  private:
    void forget(Clock::time_point now);
    std::deque<Clock::time_point> failures_;
};

}  // namespace gport::web
