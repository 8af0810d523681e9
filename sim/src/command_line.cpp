#include "gport/sim/command_line.hpp"

#include <fmt/format.h>

#include <array>
#include <charconv>
#include <cmath>
#include <functional>
#include <map>
#include <optional>

namespace gport::sim {
namespace {

using Error = OptionError;

std::optional<double> to_number(std::string_view text) {
    double v = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc{} || end != text.data() + text.size() || !std::isfinite(v)) {
        return std::nullopt;
    }
    return v;
}

// A number in [lo, hi]; the error names the option, the range and the unit.
std::optional<Error> number(std::string_view name, std::string_view text, double lo, double hi,
                            std::string_view unit, double& out) {
    const auto v = to_number(text);
    if (!v || *v < lo || *v > hi) {
        return Error{fmt::format("{} needs {} from {} to {}, got '{}'", name, unit, lo, hi, text)};
    }
    out = *v;
    return std::nullopt;
}

std::optional<Error> millis(std::string_view name, std::string_view text, Duration& out) {
    double ms = 0;
    if (auto e = number(name, text, 1, 86'400'000, "milliseconds", ms)) {
        return e;
    }
    out = std::chrono::duration_cast<Duration>(std::chrono::duration<double, std::milli>(ms));
    return std::nullopt;
}

// "ROLL,PITCH,YAW": three numbers in (0, 180], the mechanical range ± degrees.
std::optional<Error> limits(std::string_view name, std::string_view text, Vec3& out) {
    const auto bad = [&] {
        return Error{fmt::format(
            "{} needs three mechanical limits ROLL,PITCH,YAW in degrees, each above 0 and at "
            "most 180 (the range is ± that much), e.g. 45,90,170; got '{}'",
            name, text)};
    };
    std::array<double, 3> v{};
    std::string_view rest = text;
    for (std::size_t i = 0; i < v.size(); ++i) {
        const auto comma = rest.find(',');
        const bool last = i + 1 == v.size();
        if (last != (comma == std::string_view::npos)) {
            return bad();
        }
        const auto n = to_number(rest.substr(0, comma));
        if (!n || *n <= 0 || *n > 180.0) {
            return bad();
        }
        v[i] = *n;
        rest = last ? std::string_view{} : rest.substr(comma + 1);
    }
    out = Vec3{v[0], v[1], v[2]};
    return std::nullopt;
}

using ValueHandler = std::function<std::optional<Error>(std::string_view name,
                                                        std::string_view value, CommandLine& cl)>;
using FlagHandler = std::function<void(CommandLine& cl)>;

const std::map<std::string_view, ValueHandler>& value_options() {
    static const std::map<std::string_view, ValueHandler> table{
        {"--link",
         [](auto, auto v, CommandLine& cl) -> std::optional<Error> {
             if (v.empty()) {
                 return Error{"--link needs a path"};
             }
             cl.options.link_path = std::string(v);
             return std::nullopt;
         }},
        {"--rate",
         [](auto n, auto v, CommandLine& cl) {
             return number(n, v, 0, kMaxStreamRateHz, "frames per second",
                           cl.options.model.stream_rate_hz);
         }},
        {"--form",
         [](auto, auto v, CommandLine& cl) -> std::optional<Error> {
             if (v != "12" && v != "24") {
                 return Error{
                     fmt::format("--form needs 12 or 24 (data bytes of 0x87), got '{}'", v)};
             }
             cl.options.model.form = v == "12" ? AttitudeForm::kShort12 : AttitudeForm::kLong24;
             return std::nullopt;
         }},
        {"--slew",
         [](auto n, auto v, CommandLine& cl) {
             return number(n, v, 0.01, 327.67, "degrees per second", cl.options.model.slew_deg_s);
         }},
        {"--limits",
         [](auto n, auto v, CommandLine& cl) { return limits(n, v, cl.options.model.limits); }},
        {"--noise",
         [](auto n, auto v, CommandLine& cl) {
             return number(n, v, 0, 1e6, "bytes per second", cl.options.faults.noise_bytes_per_s);
         }},
        {"--corrupt-crc",
         [](auto n, auto v, CommandLine& cl) {
             return number(n, v, 0, 1, "a fraction of frames", cl.options.faults.corrupt_fraction);
         }},
        {"--merge",
         [](auto n, auto v, CommandLine& cl) -> std::optional<Error> {
             double count = 0;
             if (auto e = number(n, v, 2, 64, "frames per write", count)) {
                 return e;
             }
             if (count != std::floor(count)) {
                 return Error{fmt::format("--merge needs a whole number of frames, got '{}'", v)};
             }
             cl.options.faults.shape = WriteShape::kMerge;
             cl.options.faults.merge_count = static_cast<unsigned>(count);
             return std::nullopt;
         }},
        {"--silence-every",
         [](auto n, auto v, CommandLine& cl) {
             return millis(n, v, cl.options.faults.silence_every);
         }},
        {"--silence-for",
         [](auto n, auto v, CommandLine& cl) {
             return millis(n, v, cl.options.faults.silence_for);
         }},
        {"--vanish-every",
         [](auto n, auto v, CommandLine& cl) {
             return millis(n, v, cl.options.faults.vanish_every);
         }},
        {"--vanish-for",
         [](auto n, auto v, CommandLine& cl) {
             return millis(n, v, cl.options.faults.vanish_for);
         }},
        {"--seed",
         [](auto n, auto v, CommandLine& cl) -> std::optional<Error> {
             double seed = 0;
             if (auto e = number(n, v, 0, 4294967295.0, "a whole number", seed)) {
                 return e;
             }
             cl.options.faults.seed = static_cast<std::uint32_t>(seed);
             return std::nullopt;
         }},
        {"--record",
         [](auto, auto v, CommandLine& cl) -> std::optional<Error> {
             if (v.empty()) {
                 return Error{"--record needs a file name"};
             }
             cl.options.record_path = std::string(v);
             return std::nullopt;
         }},
        {"--replay",
         [](auto, auto v, CommandLine& cl) -> std::optional<Error> {
             if (v.empty()) {
                 return Error{"--replay needs a file name"};
             }
             cl.options.replay_path = std::string(v);
             return std::nullopt;
         }},
    };
    return table;
}

const std::map<std::string_view, FlagHandler>& flag_options() {
    static const std::map<std::string_view, FlagHandler> table{
        {"--split", [](CommandLine& cl) { cl.options.faults.shape = WriteShape::kSplit; }},
        {"--pace", [](CommandLine& cl) { cl.options.pace = true; }},
        {"--trace", [](CommandLine& cl) { cl.trace = true; }},
        {"--help", [](CommandLine& cl) { cl.help = true; }},
        {"-h", [](CommandLine& cl) { cl.help = true; }},
    };
    return table;
}

// Options given together or not at all, and conflicting choices.
std::optional<Error> check_combinations(std::span<const std::string_view> args) {
    const auto given = [&](std::string_view name) {
        for (auto a : args) {
            if (a == name ||
                (a.starts_with(name) && a.size() > name.size() && a[name.size()] == '=')) {
                return true;
            }
        }
        return false;
    };
    for (auto [a, b] : {std::pair{"--silence-every", "--silence-for"},
                        std::pair{"--vanish-every", "--vanish-for"}}) {
        if (given(a) != given(b)) {
            return Error{fmt::format("{} and {} must be given together", a, b)};
        }
    }
    if (given("--split") && given("--merge")) {
        return Error{"--split and --merge cannot be combined: choose one write shape"};
    }
    return std::nullopt;
}

}  // namespace

Result<CommandLine, OptionError> parse_command_line(std::span<const std::string_view> args) {
    CommandLine cl;
    for (std::size_t i = 0; i < args.size(); ++i) {
        std::string_view name = args[i];
        std::optional<std::string_view> value;
        if (const auto eq = name.find('=');
            name.starts_with("--") && eq != std::string_view::npos) {
            value = name.substr(eq + 1);
            name = name.substr(0, eq);
        }
        if (const auto flag = flag_options().find(name); flag != flag_options().end()) {
            if (value) {
                return Error{fmt::format("{} takes no value", name)};
            }
            flag->second(cl);
            continue;
        }
        const auto opt = value_options().find(name);
        if (opt == value_options().end()) {
            return Error{fmt::format("unknown option '{}'", args[i])};
        }
        if (!value) {
            if (i + 1 >= args.size()) {
                return Error{fmt::format("{} needs a value", name)};
            }
            value = args[++i];
        }
        if (auto e = opt->second(name, *value, cl)) {
            return *e;
        }
    }
    if (auto e = check_combinations(args)) {
        return *e;
    }
    if (auto e = validate(cl.options)) {
        return Error{*e};
    }
    return cl;
}

}  // namespace gport::sim
