// What the soak's attacks showed: problems against the required behaviour,
// the figures, and each burst's stop looked up in the gimbal's trace.
#include <fmt/format.h>

#include <algorithm>
#include <fstream>

#include "soak_attacks.hpp"

namespace gport::bench {
namespace {

using nlohmann::json;

constexpr int kSettingsPerClient = 4;  // outstanding settings requests, one client
constexpr int kSettingsInTotal = 64;   // outstanding settings requests, all clients

// A refusal that is not the daemon's fault: control held by another client,
// or the device closed (it vanished).
bool excused(const Burst& b) {
    return b.stop_code == -32003 ||
           (b.stop_code == -32000 && b.stop_message.find("not open") != std::string::npos);
}

// One line of the trace, reduced to what the burst check needs.
struct TraceEvent {
    enum Kind { kOther, kMarker, kZero, kVanish } kind = kOther;
    int marker = 0;
};

TraceEvent classify(const json& line) {
    if (line.value("event", "") == "vanish") {
        return {TraceEvent::kVanish, 0};
    }
    if (line.value("mode", "") != "speed" || !line.contains("speed")) {
        return {};
    }
    const auto& s = line["speed"];
    if (s == json{0, 0, 0}) {
        return {TraceEvent::kZero, 0};
    }
    if (s[0] == 300 && s[1] == -300) {
        return {TraceEvent::kMarker, s[2].get<int>() / 100};
    }
    return {};
}

std::vector<TraceEvent> read_trace(const std::string& path) {
    std::vector<TraceEvent> events;
    std::ifstream in(path);
    for (std::string line; std::getline(in, line);) {
        const auto j = json::parse(line, nullptr, false);
        if (j.is_object()) {
            if (const auto e = classify(j); e.kind != TraceEvent::kOther) {
                events.push_back(e);
            }
        }
    }
    return events;
}

}  // namespace

TraceVerdict check_burst_trace(const std::string& trace_path, const std::vector<Burst>& bursts) {
    TraceVerdict v;
    const auto events = read_trace(trace_path);
    std::size_t from = 0;  // bursts are sent one after another: search onwards
    for (const auto& b : bursts) {
        const auto is_mine = [&](const TraceEvent& e) {
            return e.kind == TraceEvent::kMarker && e.marker == b.marker;
        };
        const auto first =
            std::find_if(events.begin() + static_cast<std::ptrdiff_t>(from), events.end(), is_mine);
        if (first == events.end()) {
            ++v.unseen;
            continue;
        }
        // This burst's frames end where another burst's begin.
        auto end = std::find_if(first, events.end(), [&](const TraceEvent& e) {
            return e.kind == TraceEvent::kMarker && e.marker != b.marker;
        });
        const auto last = std::find_if(std::make_reverse_iterator(end),
                                       std::make_reverse_iterator(first), is_mine);
        const auto after_last = last.base();
        from = static_cast<std::size_t>(end - events.begin());
        if (!b.answered || b.stop_code != 0) {
            continue;  // refused stops are problems() already
        }
        ++v.checked;
        const auto zero = std::find_if(
            after_last, end, [](const TraceEvent& e) { return e.kind == TraceEvent::kZero; });
        if (zero != end) {
            continue;
        }
        if (std::any_of(first, end,
                        [](const TraceEvent& e) { return e.kind == TraceEvent::kVanish; })) {
            ++v.excused;
        } else if (v.problems.size() < 10) {
            v.problems.push_back(fmt::format(
                "burst {}: its stop succeeded but no zero speed followed its frames on the wire",
                b.marker));
        }
    }
    return v;
}

std::vector<std::string> Attacks::problems() const {
    std::vector<std::string> out;
    for (const auto& b : bursts_) {
        if (b.answered && b.stop_code != 0 && !excused(b) && out.size() < 10) {
            out.push_back(fmt::format("burst {}: stop refused ({}: {})", b.marker, b.stop_code,
                                      b.stop_message));
        } else if (!b.answered && out.size() < 10) {
            out.push_back(fmt::format("burst {}: no reply to its stop", b.marker));
        }
    }
    if (max_per_client_ > kSettingsPerClient) {
        out.push_back(
            fmt::format("settings flood: {} requests of one client went to the gimbal "
                        "at once (at most {} may be outstanding; the rest get -32005)",
                        max_per_client_, kSettingsPerClient));
    }
    if (max_per_wave_ > kSettingsInTotal) {
        out.push_back(
            fmt::format("settings flood: {} requests went to the gimbal in one wave (at "
                        "most {} may be outstanding in total)",
                        max_per_wave_, kSettingsInTotal));
    }
    const auto limit_ns = std::int64_t{2} * o_.idle_timeout_s * 1'000'000'000;
    if (!hoard_.empty() && max_hoard_age_ns_ > limit_ns) {
        out.push_back(fmt::format("an idle connection stayed open {:.0f} s (idle timeout {} s)",
                                  static_cast<double>(max_hoard_age_ns_) / 1e9, o_.idle_timeout_s));
    }
    return out;
}

json Attacks::figures() const {
    std::map<std::string, std::uint64_t> stops;
    for (const auto& b : bursts_) {
        ++stops[!b.answered ? "unanswered" : b.stop_code == 0 ? "ok" : std::to_string(b.stop_code)];
    }
    json codes = json::object();
    for (const auto& [code, n] : flood_codes_) {
        codes[code == 0 ? "result" : code == -1 ? "no_reply" : std::to_string(code)] = n;
    }
    return {
        {"bursts", {{"sent", bursts_.size()}, {"stop_replies", stops}}},
        {"settings_floods",
         {{"waves", floods_},
          {"replies", codes},
          {"max_to_gimbal_per_client", max_per_client_},
          {"max_to_gimbal_per_wave", max_per_wave_}}},
        {"batch_clients",
         {{"batches_written", batches_written_}, {"closed_by_daemon", batchers_closed_}}},
        {"idle_connections",
         {{"held", hoard_.size()},
          {"closed_by_daemon", hoarders_closed_},
          {"longest_open_s", static_cast<double>(max_hoard_age_ns_) / 1e9}}},
        {"sighups_sent", hups_},
    };
}

}  // namespace gport::bench
