// Argument parsing: global options anywhere, one subcommand, its options.
// Values are checked here (ranges, units) so a typo is a usage error (64)
// before any connection is made.
#include "gport/cli/options.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>

namespace gport::cli {
namespace {

using nlohmann::json;

struct CommandSpec {
    std::string_view name;
    std::string_view method;
    std::vector<std::string_view> options;  // options (and flags), without "--"
};

const std::vector<CommandSpec>& commands() {
    static const std::vector<CommandSpec> specs = {
        {"status", "status", {}},
        {"attitude", "attitude", {}},
        {"watch", "subscribe", {"rate"}},
        {"speed", "speed", {"roll", "pitch", "yaw", "for", "lease", "clamp"}},
        {"stop", "stop", {}},
        {"angle", "angle", {"roll", "pitch", "yaw", "clamp", "wait"}},
        {"center", "center", {"wait"}},
        {"lock", "lock", {}},
        {"photo", "photo", {}},
        {"record", "record", {"force"}},
        {"settings", "get_settings", {"dead-zone", "follow-speed", "inverted"}},
        {"monitor", "", {"control", "for", "color"}},
        {"help", "", {}},
    };
    return specs;
}

struct Raw {
    std::vector<std::pair<std::string, std::string>> options;  // in order given
    std::vector<std::string> positional;
};

std::optional<double> parse_number(std::string_view text) {
    double value = 0;
    auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(value)) {
        return std::nullopt;
    }
    return value;
}

double degrees(const std::string& option, const std::string& text) {
    auto value = parse_number(text);
    if (!value || std::fabs(*value) > 327.67) {
        throw UsageError{
            fmt::format("--{} {}: expected a number from -327.67 to 327.67", option, text)};
    }
    return *value;
}

int byte_value(const std::string& option, const std::string& text) {
    auto value = parse_number(text);
    if (!value || *value < 0 || *value > 255 || std::floor(*value) != *value) {
        throw UsageError{fmt::format("--{} {}: expected an integer from 0 to 255", option, text)};
    }
    return static_cast<int>(*value);
}

bool yes_no(const std::string& option, const std::string& text) {
    if (text == "yes" || text == "true" || text == "on") {
        return true;
    }
    if (text == "no" || text == "false" || text == "off") {
        return false;
    }
    throw UsageError{fmt::format("--{} {}: expected yes or no", option, text)};
}

void build_watch(Invocation& inv, const Raw& raw) {
    for (const auto& topic : raw.positional) {
        if (topic != "attitude" && topic != "link" && topic != "motion") {
            throw UsageError{
                fmt::format("watch: unknown topic \"{}\"; topics: attitude, link, motion", topic)};
        }
        if (std::find(inv.topics.begin(), inv.topics.end(), topic) == inv.topics.end()) {
            inv.topics.push_back(topic);
        }
    }
    if (inv.topics.empty()) {
        inv.topics = {"attitude", "link", "motion"};
    }
    inv.params["topics"] = inv.topics;
    for (const auto& [option, value] : raw.options) {  // only --rate is allowed here
        auto rate = parse_number(value);
        if (!rate || !(*rate >= 0.01 && *rate <= 1000)) {  // the daemon's max_rate_hz range
            throw UsageError{
                fmt::format("--rate {}: expected a rate in Hz from 0.01 to 1000", value)};
        }
        inv.rate_hz = rate;
        inv.params["max_rate_hz"] = *rate;
    }
}

// --lease MS: milliseconds, or a duration with its unit (500ms, 2s).
std::chrono::milliseconds lease_of(const std::string& text) {
    const bool digits = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
    auto lease = parse_duration(digits ? text + "ms" : text);
    if (!lease) {
        throw UsageError{fmt::format(
            "--lease {}: expected milliseconds from 1 to 86400000, or a duration such as "
            "500ms or 2s",
            text)};
    }
    return *lease;
}

// speed, angle and center: axes, --for, --lease and the flags --clamp, --wait.
void build_axes(Invocation& inv, const Raw& raw) {
    for (const auto& [option, value] : raw.options) {
        if (option == "clamp" || option == "wait") {
            inv.params[option] = true;
            inv.wait = inv.wait || option == "wait";
        } else if (option == "lease") {
            inv.params["lease_ms"] = lease_of(value).count();
        } else if (option == "for") {
            inv.duration = parse_duration(value);
            if (!inv.duration) {
                throw UsageError{fmt::format(
                    "--for {}: expected a duration such as 2s, 500ms, 1.5s or 1m", value)};
            }
            inv.params["duration_ms"] = inv.duration->count();
        } else {
            inv.params[option] = degrees(option, value);
        }
    }
}

void build_settings(Invocation& inv, const Raw& raw) {
    for (const auto& [option, value] : raw.options) {
        if (option == "inverted") {
            inv.params["inverted"] = yes_no(option, value);
        } else {
            inv.params[option == "dead-zone" ? "dead_zone" : "follow_speed"] =
                byte_value(option, value);
        }
    }
    if (!inv.params.empty()) {
        inv.method = "set_settings";
    }
}

// record [on|off [--force]]: without a state it toggles.
void build_record(Invocation& inv, const Raw& raw) {
    if (raw.positional.size() > 1) {
        throw UsageError{fmt::format("record: unexpected argument \"{}\"", raw.positional[1])};
    }
    if (!raw.positional.empty()) {
        const auto& state = raw.positional.front();
        if (state != "on" && state != "off") {
            throw UsageError{fmt::format("record: expected on or off, not \"{}\"", state)};
        }
        inv.params["on"] = state == "on";
    }
    if (!raw.options.empty()) {  // only --force is allowed here
        if (raw.positional.empty()) {
            throw UsageError{"record: --force needs on or off"};
        }
        inv.params["force"] = true;
    }
}

// monitor [--control] [--for DURATION] [--color auto|always|never]
void build_monitor(Invocation& inv, const Raw& raw) {
    static const std::map<std::string, ColorMode, std::less<>> kColors = {
        {"auto", ColorMode::kAuto}, {"always", ColorMode::kAlways}, {"never", ColorMode::kNever}};
    inv.monitor.socket = inv.socket;
    for (const auto& [option, value] : raw.options) {
        if (option == "control") {
            inv.monitor.control = true;
        } else if (option == "for") {
            inv.monitor.duration = parse_duration(value);
            if (!inv.monitor.duration) {
                throw UsageError{fmt::format(
                    "--for {}: expected a duration such as 3s, 500ms, 1.5s or 1m", value)};
            }
        } else if (auto color = kColors.find(value); color != kColors.end()) {
            inv.monitor.color = color->second;
        } else {
            throw UsageError{fmt::format("--color {}: expected auto, always or never", value)};
        }
    }
}

// Splits argv into global options (applied to `inv`), command options and
// positionals; the first positional is the command.
Raw split(const std::vector<std::string>& args, Invocation& inv, const char* env_socket) {
    Raw raw;
    if (env_socket != nullptr && *env_socket != '\0') {
        inv.socket = env_socket;
    }
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& arg = args[i];
        if (arg == "--help" || arg == "-h") {
            inv.help = true;
        } else if (arg == "--json") {
            inv.json = true;
        } else if (arg == "--force" || arg == "--clamp" || arg == "--wait" || arg == "--control") {
            raw.options.emplace_back(arg.substr(2), "");  // a flag: takes no value
        } else if (arg.rfind("--", 0) == 0 && arg.size() > 2) {
            std::string name = arg.substr(2);
            std::string value;
            if (auto eq = name.find('='); eq != std::string::npos) {
                value = name.substr(eq + 1);
                name.resize(eq);
            } else if (i + 1 < args.size()) {
                value = args[++i];
            } else {
                throw UsageError{fmt::format("--{} needs a value", name)};
            }
            if (name == "socket") {
                inv.socket = value;
            } else {
                raw.options.emplace_back(name, value);
            }
        } else if (inv.command.empty()) {
            inv.command = arg;
        } else {
            raw.positional.push_back(arg);
        }
    }
    return raw;
}

void check_options(const CommandSpec& spec, const Raw& raw) {
    for (const auto& [option, value] : raw.options) {
        if (std::find(spec.options.begin(), spec.options.end(), option) == spec.options.end()) {
            std::string allowed;
            for (auto o : spec.options) {
                allowed += fmt::format("{}--{}", allowed.empty() ? "" : ", ", o);
            }
            throw UsageError{
                fmt::format("{}: unknown option --{}{}", spec.name, option,
                            allowed.empty() ? "; it takes none" : "; options: " + allowed)};
        }
    }
    const bool takes_positionals =
        spec.name == "watch" || spec.name == "help" || spec.name == "record";
    if (!raw.positional.empty() && !takes_positionals) {
        throw UsageError{
            fmt::format("{}: unexpected argument \"{}\"", spec.name, raw.positional.front())};
    }
}

Invocation parse_or_throw(const std::vector<std::string>& args, const char* env_socket) {
    Invocation inv;
    const Raw raw = split(args, inv, env_socket);
    if (inv.help) {
        return inv;  // usage for the command named, or the overview
    }
    if (inv.command.empty()) {
        throw UsageError{"no command given"};
    }
    auto spec = std::find_if(commands().begin(), commands().end(),
                             [&](const CommandSpec& s) { return s.name == inv.command; });
    if (spec == commands().end()) {
        throw UsageError{fmt::format("unknown command \"{}\"", inv.command)};
    }
    if (spec->name == "help") {
        inv.help = true;
        inv.command = raw.positional.empty() ? "" : raw.positional.front();
        return inv;
    }
    check_options(*spec, raw);
    inv.method = spec->method;
    if (spec->name == "watch") {
        build_watch(inv, raw);
    } else if (spec->name == "speed" || spec->name == "angle" || spec->name == "center") {
        build_axes(inv, raw);
    } else if (spec->name == "settings") {
        build_settings(inv, raw);
    } else if (spec->name == "record") {
        build_record(inv, raw);
    } else if (spec->name == "monitor") {
        build_monitor(inv, raw);
    }
    return inv;
}

}  // namespace

std::optional<std::chrono::milliseconds> parse_duration(std::string_view text) {
    static const std::map<std::string_view, double> kUnits = {
        {"ms", 1.0}, {"s", 1000.0}, {"m", 60000.0}};
    const auto split_at = text.find_first_not_of("0123456789.");
    if (split_at == 0 || split_at == std::string_view::npos) {
        return std::nullopt;
    }
    auto number = parse_number(text.substr(0, split_at));
    auto unit = kUnits.find(text.substr(split_at));
    if (!number || unit == kUnits.end()) {
        return std::nullopt;
    }
    const double ms = std::round(*number * unit->second);
    if (ms < 1 || ms > 86'400'000) {
        return std::nullopt;
    }
    return std::chrono::milliseconds(static_cast<long long>(ms));
}

ParseResult parse_args(const std::vector<std::string>& args, const char* env_socket) {
    try {
        return parse_or_throw(args, env_socket);
    } catch (UsageError& error) {
        return error;
    }
}

}  // namespace gport::cli
