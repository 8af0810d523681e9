#include "report.hpp"

#include <fmt/format.h>

#include "../e2e/lines.hpp"

namespace gport::bench::relay {

void print_header(std::ostream& out) {
    out << fmt::format("{:<20} {:>5} {:>5} {:>4} {:>8} {:>8} {:>8} {:>5} {:>6} {:>5}  {}\n",
                       "scenario", "sent", "seen", "lost", "p50 ms", "p99 ms", "max ms", "lease",
                       "drops", "alive", "flood")
        << std::flush;
}

void print_row(std::ostream& out, ScenarioResult& r) {
    auto& v = r.probe.delays_ms;
    const double p50 = quantile(v, 0.5);
    const double p99 = quantile(v, 0.99);
    const double max = quantile(v, 1.0);
    out << fmt::format(
        "{:<20} {:>5} {:>5} {:>4} {:>8.1f} {:>8.1f} {:>8.1f} {:>5} {:>6} {:>5}  {}\n",
        r.scenario.name, r.probe.sent, v.size(), r.probe.lost(), p50, p99, max, r.lease_endings,
        r.relay_drops, r.relay_alive ? "yes" : "NO", r.flood_rate);
    if (r.probe.lost() > 0) {
        auto& late = r.probe.late_ms;
        const auto never = static_cast<std::size_t>(r.probe.lost()) - late.size();
        const double wait_s = static_cast<double>(kLateWaitNs) / 1e9;
        out << fmt::format(
            "    lost: {} on the wire later ({:.0f} to {:.0f} ms), {} not within "
            "{:.0f} s\n",
            late.size(), quantile(late, 0.0), quantile(late, 1.0), never, wait_s);
    }
    if (!r.notes.empty()) {
        out << "    " << r.notes << "\n";
    }
    out << std::flush;
}

std::string verdict(ScenarioResult& r, const Options& o) {
    if (!r.relay_alive) {
        return r.scenario.relay + " relay is not running any more";
    }
    const bool budget = o.budget_p99_ms || o.budget_max_ms;
    if ((budget || o.fail_on_lost) && r.probe.lost() > 0) {
        return fmt::format("{} of {} stops never reached the wire within 1 s", r.probe.lost(),
                           r.probe.sent);
    }
    auto& v = r.probe.delays_ms;
    if (o.budget_p99_ms && quantile(v, 0.99) > *o.budget_p99_ms) {
        return fmt::format("p99 {:.1f} ms over the budget {} ms", quantile(v, 0.99),
                           *o.budget_p99_ms);
    }
    if (o.budget_max_ms && quantile(v, 1.0) > *o.budget_max_ms) {
        return fmt::format("max {:.1f} ms over the budget {} ms", quantile(v, 1.0),
                           *o.budget_max_ms);
    }
    return "";
}

}  // namespace gport::bench::relay
