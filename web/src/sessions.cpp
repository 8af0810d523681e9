#include "gport/web/sessions.hpp"

#include <algorithm>

#include "gport/web/limits.hpp"

namespace gport::web {

std::string Sessions::open(Role role, Clock::time_point now) {
    while (sessions_.size() >= kMaxSessions) {
        const auto oldest = std::min_element(
            sessions_.begin(), sessions_.end(),
            [](const auto& a, const auto& b) { return a.second.used < b.second.used; });
        sessions_.erase(oldest);
    }
    auto id = random_hex(32);
    sessions_[id] = Session{role, now};
    return id;
}

std::optional<Role> Sessions::find(const std::string& id, Clock::time_point now) {
    const auto it = sessions_.find(id);
    if (it == sessions_.end()) {
        return std::nullopt;
    }
    if (now - it->second.used > kSessionIdle) {
        sessions_.erase(it);
        return std::nullopt;
    }
    it->second.used = now;
    return it->second.role;
}

void Sessions::close(const std::string& id) {
    sessions_.erase(id);
}

void LoginGuard::forget(Clock::time_point now) {
    while (!failures_.empty() && now - failures_.front() >= kLoginWindow) {
        failures_.pop_front();
    }
}

std::optional<int> LoginGuard::blocked(Clock::time_point now) {
    forget(now);
    if (failures_.size() < static_cast<std::size_t>(kMaxLoginFailures)) {
        return std::nullopt;
    }
    const auto left = kLoginWindow - (now - failures_.front());
    return static_cast<int>(std::chrono::ceil<std::chrono::seconds>(left).count());
}

void LoginGuard::failed(Clock::time_point now) {
    forget(now);
    failures_.push_back(now);
}

}  // namespace gport::web
