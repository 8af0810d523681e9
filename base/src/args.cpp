#include "gport/base/args.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <functional>
#include <map>

#include "gport/version.hpp"

namespace gport::args {
namespace {

std::optional<double> parse_number(std::string_view text) {
    if (text.starts_with('+')) {
        text.remove_prefix(1);
    }
    double value = 0;
    auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || error != std::errc() || end != text.data() + text.size() ||
        !std::isfinite(value)) {
        return std::nullopt;
    }
    return value;
}

std::string duration_text(std::chrono::milliseconds ms) {
    if (ms.count() % 3'600'000 == 0) {
        return fmt::format("{}h", ms.count() / 3'600'000);
    }
    if (ms.count() % 60'000 == 0) {
        return fmt::format("{}m", ms.count() / 60'000);
    }
    if (ms.count() % 1000 == 0) {
        return fmt::format("{}s", ms.count() / 1000);
    }
    return fmt::format("{}ms", ms.count());
}

}  // namespace

void configure(CLI::App& app, std::string_view exit_statuses) {
    app.set_help_flag("-h,--help", "print this help and exit");
    app.set_version_flag("--version", app.get_name() + " " + std::string(kVersion),
                         "print the version and exit");
    app.fallthrough();
    app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    app.footer(std::string(exit_statuses) + "\n");
}

std::optional<std::chrono::milliseconds> parse_duration(std::string_view text) {
    static const std::map<std::string_view, double> kUnits = {
        {"ms", 1.0}, {"s", 1000.0}, {"m", 60000.0}, {"h", 3600000.0}};
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
    if (ms < 1 || ms > 1e15) {
        return std::nullopt;
    }
    return std::chrono::milliseconds(static_cast<long long>(ms));
}

CLI::Validator number_in(double min, double max, std::string what) {
    auto allowed = fmt::format("expected {} from {} to {}", what, min, max);
    return CLI::Validator(
        [min, max, allowed](std::string& text) -> std::string {
            auto value = parse_number(text);
            if (!value || *value < min || *value > max) {
                return fmt::format("{}: {}", text, allowed);
            }
            text = fmt::format("{}", *value);  // without the + CLI11 would also take
            return {};
        },
        fmt::format("{} to {}", min, max));
}

CLI::Validator integer_in(long long min, long long max) {
    auto allowed = fmt::format("expected an integer from {} to {}", min, max);
    return CLI::Validator(
        [min, max, allowed](std::string& text) -> std::string {
            auto value = parse_number(text);
            if (!value || *value < static_cast<double>(min) || *value > static_cast<double>(max) ||
                std::floor(*value) != *value) {
                return fmt::format("{}: {}", text, allowed);
            }
            text = fmt::format("{}", static_cast<long long>(*value));
            return {};
        },
        fmt::format("{} to {}", min, max));
}

CLI::Validator duration_in(std::chrono::milliseconds min, std::chrono::milliseconds max,
                           bool bare_ms) {
    auto allowed = fmt::format("expected a duration from {} to {}, such as 500ms, 2s or 1.5m{}",
                               duration_text(min), duration_text(max),
                               bare_ms ? " (a bare number counts in milliseconds)" : "");
    return CLI::Validator(
        [min, max, bare_ms, allowed](std::string& text) -> std::string {
            const bool digits =
                !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
            auto value = parse_duration(bare_ms && digits ? text + "ms" : text);
            if (!value || *value < min || *value > max) {
                return fmt::format("{}: {}", text, allowed);
            }
            return {};
        },
        fmt::format("{} to {}", duration_text(min), duration_text(max)));
}

CLI::Validator one_of(std::vector<std::string> names) {
    const auto last = names.back();
    names.pop_back();
    const auto allowed = names.size() == 1
                             ? fmt::format("expected {} or {}", names.front(), last)
                             : fmt::format("expected one of {}, {}", fmt::join(names, ", "), last);
    names.push_back(last);
    return CLI::Validator(
        [names, allowed](std::string& text) -> std::string {
            if (std::find(names.begin(), names.end(), text) == names.end()) {
                return fmt::format("{}: {}", text, allowed);
            }
            return {};
        },
        fmt::format("{}", fmt::join(names, "|")));
}

std::string leftover_problem(const CLI::App& app) {
    const auto extras = app.remaining();
    if (extras.empty()) {
        return {};
    }
    const auto& first = extras.front();
    if (!first.starts_with("-")) {
        return fmt::format("unexpected argument \"{}\"; {} takes only options", first,
                           app.get_name());
    }
    std::vector<std::string> names;
    for (const auto* option : app.get_options()) {
        names.push_back(option->get_name());
    }
    return fmt::format("unknown option {}; the options are {}", first.substr(0, first.find('=')),
                       fmt::join(names, ", "));
}

CLI::Validator check_with(std::function<std::optional<std::string>(std::string_view)> check) {
    return CLI::Validator(
        [check](std::string& text) -> std::string { return check(text).value_or(""); }, "");
}

std::string message_of(const CLI::ParseError& error) {
    const std::string what = error.what();
    // CLI11: "--yaw: 1 required DEG/S:-327.67 to 327.67 missing".
    if (dynamic_cast<const CLI::ArgumentMismatch*>(&error) != nullptr &&
        what.find(" required ") != std::string::npos && what.ends_with(" missing")) {
        return fmt::format("{} needs a value", what.substr(0, what.find(':')));
    }
    return what;
}

bool is_request(const CLI::ParseError& error) {
    return error.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success);
}

}  // namespace gport::args
