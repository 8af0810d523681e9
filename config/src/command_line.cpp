#include "gport/config/command_line.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <vector>

#include "checks.hpp"
#include "gport/version.hpp"

namespace gport::config {
namespace {

// Checks a value and stores it; returns the problem, if any.
using Setter = std::optional<std::string> (*)(CommandLine&, std::string_view value);

struct Option {
    std::string_view name;
    std::string_view value_name;  // empty: a flag without a value
    Setter set;
};

std::optional<std::string> store(std::optional<std::string>& target, std::string_view value,
                                 std::optional<std::string> problem) {
    if (!problem) {
        target = std::string(value);
    }
    return problem;
}

std::optional<std::string> check_config_path(std::string_view path) {
    if (path.empty()) {
        return "must name a file, got an empty string";
    }
    return std::nullopt;
}

const std::array<Option, 8> kOptions = {{
    {"--config", "FILE",
     [](CommandLine& c, std::string_view v) {
         return store(c.config_path, v, check_config_path(v));
     }},
    {"--device", "PATH",
     [](CommandLine& c, std::string_view v) {
         return store(c.device, v, detail::check_device_path(v));
     }},
    {"--socket", "PATH",
     [](CommandLine& c, std::string_view v) {
         return store(c.socket_path, v, detail::check_socket_path(v));
     }},
    {"--log-level", "LEVEL",
     [](CommandLine& c, std::string_view v) {
         return store(c.log_level, v, detail::check_log_level(v));
     }},
    {"--simulate", "",
     [](CommandLine& c, std::string_view) -> std::optional<std::string> {
         c.simulate = true;
         return std::nullopt;
     }},
    {"--help", "",
     [](CommandLine& c, std::string_view) -> std::optional<std::string> {
         c.help = true;
         return std::nullopt;
     }},
    {"-h", "",
     [](CommandLine& c, std::string_view) -> std::optional<std::string> {
         c.help = true;
         return std::nullopt;
     }},
    {"--version", "",
     [](CommandLine& c, std::string_view) -> std::optional<std::string> {
         c.version = true;
         return std::nullopt;
     }},
}};

std::string option_names() {
    std::vector<std::string_view> names;
    for (const auto& option : kOptions) {
        names.push_back(option.name);
    }
    return fmt::format("{}", fmt::join(names, ", "));
}

const Option* find_option(std::string_view name) {
    const auto it = std::find_if(kOptions.begin(), kOptions.end(),
                                 [&](const Option& option) { return option.name == name; });
    return it == kOptions.end() ? nullptr : &*it;
}

}  // namespace

Result<CommandLine> parse_command_line(std::span<const char* const> args) {
    CommandLine command_line;
    std::vector<std::string> errors;
    for (std::size_t i = 1; i < args.size(); ++i) {
        const std::string_view arg = args[i] != nullptr ? args[i] : "";
        const auto equals = arg.starts_with("--") ? arg.find('=') : std::string_view::npos;
        const auto name = arg.substr(0, equals);
        const Option* option = find_option(name);
        if (option == nullptr) {
            errors.push_back(arg.starts_with("-")
                                 ? fmt::format("unknown option {}; the options are {}",
                                               detail::json_quoted(name), option_names())
                                 : fmt::format("unexpected argument {}; gportd takes only options",
                                               detail::json_quoted(arg)));
            continue;
        }
        std::string_view value;
        if (option->value_name.empty()) {
            if (equals != std::string_view::npos) {
                errors.push_back(fmt::format("{}: takes no value", option->name));
                continue;
            }
        } else if (equals != std::string_view::npos) {
            value = arg.substr(equals + 1);
        } else if (i + 1 < args.size() && args[i + 1] != nullptr &&
                   !std::string_view(args[i + 1]).starts_with("--")) {
            value = args[++i];
        } else {
            errors.push_back(fmt::format("{}: missing value; use {} {}", option->name, option->name,
                                         option->value_name));
            continue;
        }
        if (auto problem = option->set(command_line, value)) {
            errors.push_back(fmt::format("{}: {}", option->name, *problem));
        }
    }
    if (!errors.empty()) {
        return Errors{std::move(errors)};
    }
    return command_line;
}

std::string usage() {
    return fmt::format(
        "Usage: gportd [OPTIONS]\n"
        "\n"
        "Serves a G-Port camera gimbal to local clients over a Unix socket.\n"
        "\n"
        "Options:\n"
        "  --config FILE      read the settings from FILE (default {0};\n"
        "                     if that file does not exist, built-in defaults apply)\n"
        "  --device PATH      the gimbal's serial device (overrides serial.device)\n"
        "  --socket PATH      the Unix socket to serve (overrides socket.path)\n"
        "  --log-level LEVEL  {1}\n"
        "                     (overrides log.level)\n"
        "  --simulate         drive the built-in simulated gimbal instead of a device\n"
        "  -h, --help         print this help and exit\n"
        "  --version          print the version and exit\n"
        "\n"
        "Options with a value also take the form --option=VALUE. Command-line values\n"
        "override the config file.\n"
        "\n"
        "Exit status: 0 after a clean shutdown, {2} for a command-line error, {3} for a\n"
        "configuration error.\n",
        kDefaultConfigPath, detail::log_levels_text(), kExitUsage, kExitConfig);
}

std::string version_text() {
    return fmt::format("gportd {}\n", kVersion);
}

}  // namespace gport::config
