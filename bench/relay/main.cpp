// bench_relay_stop: how fast a stop relayed by gport-web and by gport-mavlink
// reaches the gimbal's wire at 115200 baud while other peers flood the relay
// (docs/performance.md, "Stops through the relays").
//
//   bench_relay_stop [--stops N] [--scenario NAME,...] [--flood-seconds S]
//                    [--budget-p99-ms X --budget-max-ms Y] [--fail-on-lost]
//
// Exit 0; 1 when a relay died, when a scenario broke a budget or lost a stop
// with --budget-* or --fail-on-lost, or when the set-up failed.
#include <fmt/format.h>

#include <chrono>
#include <iostream>
#include <stdexcept>
#include <thread>
#include <vector>

#include "../e2e/posix.hpp"
#include "options.hpp"
#include "report.hpp"
#include "rig.hpp"
#include "scenarios.hpp"

namespace gport::bench::relay {
namespace {

constexpr auto kSettle =
    std::chrono::milliseconds(1500);  // gport-web answers a flood past its rate after 1 s

void print_exits(const Exits& exits) {
    std::cout << fmt::format(
        "exit statuses after SIGTERM: gport-web {}, gport-mavlink {}, gportd {} (0 = clean)\n",
        exits.gport_web, exits.gport_mavlink, exits.gportd);
}

// Runs every scenario on one rig; returns the failures.
std::vector<std::string> run_all(Rig& rig, const Options& options) {
    std::cout << fmt::format(
        "bench_relay_stop: {} stops a scenario, floods {:.1f} s ahead, line 115200 baud, load {}\n"
        "stop sent -> zero-speed 0x85 fully on the gimbal's wire; lease = motions gportd ended "
        "on their lease meanwhile; drops = the relay's lost-gportd log lines\n",
        options.stops, options.flood_seconds, load_average());
    print_header(std::cout);
    std::vector<std::string> failures;
    for (const auto& scenario : options.scenarios) {
        auto result = scenario.relay == "web" ? run_web_scenario(rig, options, scenario)
                                              : run_mavlink_scenario(rig, options, scenario);
        print_row(std::cout, result);
        // Let the relay close what the flood left (answers still owed by gportd).
        std::this_thread::sleep_for(kSettle);
        if (const auto why = verdict(result, options); !why.empty()) {
            failures.push_back(scenario.name + ": " + why);
        }
    }
    return failures;
}

int run(const Options& options) {
    raise_fd_limit();
    Rig rig(options);
    std::vector<std::string> failures;
    try {
        failures = run_all(rig, options);
    } catch (...) {
        rig.keep_logs();
        std::cerr << "bench_relay_stop: logs kept in " << rig.dir() << "\n";
        throw;
    }
    const Exits exits = rig.finish();
    print_exits(exits);
    if (exits.gport_web != 0 || exits.gport_mavlink != 0) {
        failures.push_back("a relay did not exit cleanly on SIGTERM");
    }
    if (options.keep_logs || !failures.empty()) {
        rig.keep_logs();
        std::cerr << "bench_relay_stop: logs kept in " << rig.dir() << "\n";
    }
    for (const auto& failure : failures) {
        std::cerr << "bench_relay_stop: FAIL " << failure << "\n";
    }
    return failures.empty() ? 0 : 1;
}

}  // namespace
}  // namespace gport::bench::relay

int main(int argc, char** argv) {
    try {
        const auto options = gport::bench::relay::parse_options(argc, argv);
        return options ? gport::bench::relay::run(*options) : 0;
    } catch (const std::exception& e) {
        std::cerr << "bench_relay_stop: " << e.what() << "\n";
        return 1;
    }
}
