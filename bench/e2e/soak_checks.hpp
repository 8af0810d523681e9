// What the soak driver checks while it runs: that every speed motion whose
// owner disconnected ends soon after (the deadman), that the daemon's status
// counters only grow and agree with each other, and that its resident
// memory stays bounded.
#pragma once

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace gport::bench {

// Follows `motion` notifications and client disconnects.
class DeadmanCheck {
  public:
    explicit DeadmanCheck(std::int64_t limit_ns) : limit_ns_(limit_ns) {}

    // A `motion` notification's params, as the watcher read it at t_ns.
    void on_motion(const nlohmann::json& params, std::int64_t t_ns);
    // A driver client with daemon id `id` closed its connection at t_ns.
    void on_disconnect(std::uint64_t id, std::int64_t t_ns);
    // Flags a motion whose owner left more than the limit ago and still runs.
    void check(std::int64_t t_ns);

    std::uint64_t orphaned() const { return orphaned_; }  // motions whose owner left
    std::uint64_t violations() const { return violations_; }
    const std::map<std::string, std::uint64_t>& end_reasons() const { return end_reasons_; }
    double max_end_ms() const { return max_end_ms_; }  // owner gone -> ended, worst seen
    std::vector<std::string> violation_notes() const { return notes_; }

  private:
    struct Motion {
        std::uint64_t owner = 0;
        std::int64_t seen_ns = 0;
        bool flagged = false;
    };
    std::int64_t orphaned_since(const Motion& m) const;

    std::int64_t limit_ns_;
    std::optional<Motion> current_;
    std::map<std::uint64_t, std::int64_t> gone_;  // daemon client id -> when it closed
    std::uint64_t orphaned_ = 0;
    std::uint64_t violations_ = 0;
    double max_end_ms_ = 0;
    std::map<std::string, std::uint64_t> end_reasons_;  // of orphaned motions
    std::vector<std::string> notes_;
};

// Status counters sampled over time.
class CounterCheck {
  public:
    void on_status(const nlohmann::json& counters);
    std::uint64_t samples() const { return samples_; }
    const std::vector<std::string>& problems() const { return problems_; }
    const nlohmann::json& last() const { return last_; }

  private:
    void problem(std::string text);

    nlohmann::json last_;
    std::uint64_t samples_ = 0;
    std::vector<std::string> problems_;
};

// VmRSS once a second: bounded, and not still growing in the second half.
struct RssVerdict {
    long first_half_max_kib = 0;
    long second_half_max_kib = 0;
    long max_kib = 0;
    bool ok = false;
};
RssVerdict judge_rss(const std::vector<long>& samples_kib, long margin_kib, long limit_kib);

}  // namespace gport::bench
