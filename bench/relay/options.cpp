#include "options.hpp"

#include <iostream>
#include <sstream>
#include <stdexcept>

namespace gport::bench::relay {
namespace {

constexpr const char* kUsage =
    "usage: bench_relay_stop [--stops N] [--scenario NAME[,NAME...]]... [--flood-seconds S]\n"
    "                        [--spacing-ms MS] [--budget-p99-ms X] [--budget-max-ms Y]\n"
    "                        [--fail-on-lost] [--keep-logs] [--gportd PATH]\n"
    "                        [--gport-web PATH] [--gport-mavlink PATH]\n"
    "scenarios: web/none web/view-status web/view-mixed web/csv web/jog mavlink/none\n"
    "           mavlink/gcs-camera mavlink/gcs-angles; also all, web, mavlink\n";

// Adds the scenarios `name` stands for (a name, a relay or "all").
void add_scenarios(const std::string& name, std::vector<Scenario>& chosen) {
    bool found = false;
    for (const auto& s : all_scenarios()) {
        if (name == "all" || name == s.name || name == s.relay) {
            chosen.push_back(s);
            found = true;
        }
    }
    if (!found) {
        throw std::invalid_argument("--scenario: unknown scenario '" + name + "'\n" + kUsage);
    }
}

double positive(const std::string& option, const std::string& value) {
    std::size_t used = 0;
    double v = 0;
    try {
        v = std::stod(value, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != value.size() || !(v > 0)) {
        throw std::invalid_argument(option + " needs a number above 0, not '" + value + "'");
    }
    return v;
}

// Applies one option that takes a value.
void apply(Options& o, const std::string& option, const std::string& value) {
    if (option == "--stops") {
        o.stops = static_cast<int>(positive(option, value));
    } else if (option == "--scenario") {
        std::stringstream list(value);
        for (std::string name; std::getline(list, name, ',');) {
            add_scenarios(name, o.scenarios);
        }
    } else if (option == "--flood-seconds") {
        o.flood_seconds = positive(option, value);
    } else if (option == "--spacing-ms") {
        o.spacing_ms = static_cast<int>(positive(option, value));
    } else if (option == "--budget-p99-ms") {
        o.budget_p99_ms = positive(option, value);
    } else if (option == "--budget-max-ms") {
        o.budget_max_ms = positive(option, value);
    } else if (option == "--gportd") {
        o.gportd = value;
    } else if (option == "--gport-web") {
        o.gport_web = value;
    } else if (option == "--gport-mavlink") {
        o.gport_mavlink = value;
    } else {
        throw std::invalid_argument("unknown option " + option + "\n" + kUsage);
    }
}

}  // namespace

const std::vector<Scenario>& all_scenarios() {
    static const std::vector<Scenario> all = {
        {"web/none", "web", "none"},
        {"web/view-status", "web", "view-status"},
        {"web/view-mixed", "web", "view-mixed"},
        {"web/csv", "web", "csv"},
        {"web/jog", "web", "jog"},
        {"mavlink/none", "mavlink", "none"},
        {"mavlink/gcs-camera", "mavlink", "gcs-camera"},
        {"mavlink/gcs-angles", "mavlink", "gcs-angles"},
    };
    return all;
}

std::optional<Options> parse_options(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string option = argv[i];
        if (option == "--help" || option == "-h") {
            std::cout << kUsage;
            return std::nullopt;
        }
        if (option == "--fail-on-lost") {
            o.fail_on_lost = true;
        } else if (option == "--keep-logs") {
            o.keep_logs = true;
        } else if (i + 1 >= argc) {
            throw std::invalid_argument(option + " needs a value\n" + kUsage);
        } else {
            apply(o, option, argv[++i]);
        }
    }
    if (o.scenarios.empty()) {
        o.scenarios = all_scenarios();
    }
    if (o.spacing_ms < 60) {
        throw std::invalid_argument("--spacing-ms must be at least 60");
    }
    return o;
}

}  // namespace gport::bench::relay
