#include "soak_checks.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace gport::bench {

using nlohmann::json;

std::int64_t DeadmanCheck::orphaned_since(const Motion& m) const {
    const auto gone = gone_.find(m.owner);
    return gone == gone_.end() ? -1 : std::max(gone->second, m.seen_ns);
}

void DeadmanCheck::on_motion(const json& params, std::int64_t t_ns) {
    const auto change = params.value("change", "");
    const auto& owner = params.contains("owner") ? params["owner"] : json();
    const auto owner_id = owner.is_object() ? owner.value("id", std::uint64_t{0}) : 0;
    const bool speed = params.value("mode", "") == "speed";
    if (change == "ended") {
        if (current_ && current_->owner == owner_id) {
            if (const auto since = orphaned_since(*current_); since >= 0) {
                ++end_reasons_[params.value("reason", "?")];
                max_end_ms_ = std::max(max_end_ms_, static_cast<double>(t_ns - since) / 1e6);
            }
        }
        current_.reset();
        return;
    }
    // started or replaced: a new command took over from an orphaned motion.
    if (current_ && orphaned_since(*current_) >= 0) {
        ++end_reasons_["replaced"];
        max_end_ms_ =
            std::max(max_end_ms_, static_cast<double>(t_ns - orphaned_since(*current_)) / 1e6);
    }
    // Only speed motions have a keepalive that the deadman must stop.
    current_.reset();
    if (speed && owner_id != 0) {
        current_ = Motion{owner_id, t_ns, false};
        if (gone_.contains(owner_id)) {
            ++orphaned_;  // its owner had already left when we heard of it
        }
    }
}

void DeadmanCheck::on_disconnect(std::uint64_t id, std::int64_t t_ns) {
    gone_[id] = t_ns;
    if (current_ && current_->owner == id) {
        ++orphaned_;
    }
}

void DeadmanCheck::check(std::int64_t t_ns) {
    if (!current_ || current_->flagged) {
        return;
    }
    const auto since = orphaned_since(*current_);
    if (since >= 0 && t_ns - since > limit_ns_) {
        current_->flagged = true;
        ++violations_;
        notes_.push_back(fmt::format("motion of client {} still running {:.0f} ms after it left",
                                     current_->owner, static_cast<double>(t_ns - since) / 1e6));
    }
}

void CounterCheck::problem(std::string text) {
    if (problems_.size() < 20) {
        problems_.push_back(std::move(text));
    }
}

void CounterCheck::on_status(const json& counters) {
    ++samples_;
    for (const auto& [key, value] : counters.items()) {
        if (!value.is_number_unsigned()) {
            problem(fmt::format("counter {} is not a non-negative integer: {}", key, value.dump()));
            continue;
        }
        if (last_.contains(key) && value.get<std::uint64_t>() < last_[key].get<std::uint64_t>()) {
            problem(fmt::format("counter {} went down: {} -> {}", key, last_[key].dump(),
                                value.dump()));
        }
    }
    const auto n = [&](const char* key) { return counters.value(key, std::uint64_t{0}); };
    if (n("frames_in") < n("attitude_frames")) {
        problem(
            fmt::format("frames_in {} < attitude_frames {}", n("frames_in"), n("attitude_frames")));
    }
    if (n("bytes_in") < 5 * n("frames_in")) {
        problem(fmt::format("bytes_in {} < 5 x frames_in {}", n("bytes_in"), n("frames_in")));
    }
    if (n("bytes_out") < 5 * n("frames_out")) {
        problem(fmt::format("bytes_out {} < 5 x frames_out {}", n("bytes_out"), n("frames_out")));
    }
    if (n("bytes_in") < n("garbage_bytes")) {
        problem(fmt::format("garbage_bytes {} > bytes_in {}", n("garbage_bytes"), n("bytes_in")));
    }
    last_ = counters;
}

RssVerdict judge_rss(const std::vector<long>& samples_kib, long margin_kib, long limit_kib) {
    RssVerdict v;
    if (samples_kib.size() < 4) {
        return v;  // too short a run to say anything
    }
    const auto middle = samples_kib.begin() + static_cast<std::ptrdiff_t>(samples_kib.size() / 2);
    v.first_half_max_kib = *std::max_element(samples_kib.begin(), middle);
    v.second_half_max_kib = *std::max_element(middle, samples_kib.end());
    v.max_kib = std::max(v.first_half_max_kib, v.second_half_max_kib);
    v.ok = v.second_half_max_kib <= v.first_half_max_kib + margin_kib && v.max_kib <= limit_kib;
    return v;
}

}  // namespace gport::bench
