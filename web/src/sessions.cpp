#include "gport/web/sessions.hpp"

#include <algorithm>
#include <sstream>

#include "crypto.hpp"
#include "gport/web/limits.hpp"
#include "state_file.hpp"

namespace gport::web {

// Each role has half of kMaxSessions, and a login ends only its own role's
// least recently used session: a view token's holder logging in again and
// again never ends the operator's control session (its Stop then answered
// 401), whose use moves only with its HTTP requests.
std::string Sessions::open(Role role, Clock::time_point now) {
    const auto same_role = [role](const auto& entry) { return entry.second.role == role; };
    while (static_cast<std::size_t>(std::count_if(sessions_.begin(), sessions_.end(), same_role)) >=
           kMaxSessions / 2) {
        auto oldest = sessions_.end();
        for (auto it = sessions_.begin(); it != sessions_.end(); ++it) {
            if (same_role(*it) &&
                (oldest == sessions_.end() || it->second.used < oldest->second.used)) {
                oldest = it;
            }
        }
        sessions_.erase(oldest);
    }
    auto id = random_hex(32);
    sessions_[sha256_hex(id)] = Session{role, now};
    save();
    return id;
}

std::optional<Role> Sessions::find(const std::string& id, Clock::time_point now) {
    const auto it = sessions_.find(sha256_hex(id));
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
    if (sessions_.erase(sha256_hex(id)) > 0) {
        save();
    }
}

// One line a session: HASH ROLE LAST-USE (Unix seconds).
std::string Sessions::persist(const std::string& path) {
    path_ = path;
    std::string problem;
    const auto lines = read_state_file(path, problem);
    const auto now = Clock::now();
    const auto wall = std::chrono::system_clock::now();
    for (const auto& line : lines.value_or(std::vector<std::string>{})) {
        std::istringstream in(line);
        std::string hash;
        std::string role;
        long long used = 0;
        if (!(in >> hash >> role >> used) || hash.size() != 64 ||
            (role != "control" && role != "view")) {
            continue;
        }
        const auto age = wall - std::chrono::system_clock::time_point(std::chrono::seconds(used));
        if (age < std::chrono::seconds(0) || age > kSessionIdle ||
            sessions_.size() >= kMaxSessions) {
            continue;
        }
        sessions_[hash] = Session{role == "control" ? Role::kControl : Role::kView,
                                  now - std::chrono::duration_cast<Clock::duration>(age)};
    }
    return problem;
}

std::string Sessions::save() const {
    if (path_.empty()) {
        return "";
    }
    const auto now = Clock::now();
    const auto wall = std::chrono::system_clock::now();
    std::vector<std::string> lines;
    for (const auto& [hash, session] : sessions_) {
        const auto used = wall - std::chrono::duration_cast<std::chrono::system_clock::duration>(
                                     now - session.used);
        lines.push_back(
            hash + " " + std::string(role_name(session.role)) + " " +
            std::to_string(
                std::chrono::duration_cast<std::chrono::seconds>(used.time_since_epoch()).count()));
    }
    std::string problem;
    write_state_file(path_, lines, problem);
    return problem;
}

namespace {

using Clock = LoginGuard::Clock;

void forget(std::deque<Clock::time_point>& times, Clock::time_point now) {
    while (!times.empty() && now - times.front() >= kLoginWindow) {
        times.pop_front();
    }
}

// The seconds until `times` has room for one more of `limit`, if it has none.
std::optional<int> wait(std::deque<Clock::time_point>& times, std::size_t limit,
                        Clock::time_point now) {
    forget(times, now);
    if (times.size() < limit) {
        return std::nullopt;
    }
    const auto left = kLoginWindow - (now - times[times.size() - limit]);
    return static_cast<int>(std::chrono::ceil<std::chrono::seconds>(left).count());
}

void add(std::deque<Clock::time_point>& times, std::size_t limit, Clock::time_point now) {
    forget(times, now);
    times.push_back(now);
    while (times.size() > limit) {
        times.pop_front();
    }
}

}  // namespace

std::optional<int> LoginGuard::blocked(const std::string& address, Clock::time_point now) {
    auto longest = wait(all_, kMaxLoginFailuresTotal, now);
    const auto it = addresses_.find(address);
    if (it == addresses_.end()) {
        return longest;
    }
    const auto mine = wait(it->second.times, kMaxLoginFailures, now);
    if (it->second.times.empty()) {
        order_.erase(it->second.order);
        addresses_.erase(it);
    }
    if (mine && (!longest || *mine > *longest)) {
        longest = mine;
    }
    return longest;
}

void LoginGuard::failed(const std::string& address, Clock::time_point now) {
    add(all_, kMaxLoginFailuresTotal, now);
    add(entry(address).times, kMaxLoginFailures, now);
}

LoginGuard::Failures& LoginGuard::entry(const std::string& address) {
    if (const auto it = addresses_.find(address); it != addresses_.end()) {
        order_.splice(order_.end(), order_, it->second.order);
        return it->second;
    }
    while (addresses_.size() >= kMaxLoginAddresses) {
        addresses_.erase(order_.front());
        order_.pop_front();
    }
    order_.push_back(address);
    auto& added = addresses_[address];
    added.order = std::prev(order_.end());
    return added;
}

}  // namespace gport::web
