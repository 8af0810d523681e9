// gportd's command line on CLI11, with the conventions the three programs
// share (gport/base/args.hpp). Values are checked like the config file's.
#include "gport/config/command_line.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <iterator>
#include <vector>

#include "checks.hpp"
#include "gport/base/args.hpp"
#include "gport/version.hpp"

namespace gport::config {
namespace {

std::optional<std::string> check_config_path(std::string_view path) {
    if (path.empty()) {
        return "must name a file, got an empty string";
    }
    return std::nullopt;
}

class Parser {
  public:
    Parser()
        : app_("gportd serves a G-Port camera gimbal to local clients over a Unix socket.",
               "gportd") {
        args::configure(app_, fmt::format("Options with a value also take the form "
                                          "--option=VALUE. Command-line values\n"
                                          "override the config file.\n\n"
                                          "Exit status: 0 after a clean shutdown, {} when it "
                                          "cannot serve (e.g. cannot\ncreate its socket: as a "
                                          "user, --socket \"$XDG_RUNTIME_DIR/gportd.sock\"), {} "
                                          "for a\ncommand-line error, {} for a configuration "
                                          "error.",
                                          gport::kExitFailure, kExitUsage, kExitConfig));
        app_.allow_extras();  // named by args::leftover_problem
        option("--config", config_,
               fmt::format("read the settings from FILE (default {}, if it exists)",
                           default_config_path()),
               "FILE", check_config_path);
        option("--device", device_, "the gimbal's serial device (overrides serial.device)", "PATH",
               detail::check_device_path);
        option("--socket", socket_, "the Unix socket to serve (overrides socket.path)", "PATH",
               detail::check_socket_path);
        option("--log-level", log_level_,
               fmt::format("{} (overrides log.level)", detail::log_levels_text()), "LEVEL",
               detail::check_log_level);
        option("--state-dir", state_dir_,
               "keep the capture log in DIR (overrides captures.dir and $STATE_DIRECTORY)", "DIR",
               detail::check_state_dir);
        app_.add_flag("--simulate", simulate_,
                      "drive the built-in simulated gimbal instead of a device");
        app_.add_option("--probe", probe_,
                        "find the G-Port: listen on DEVICEs (default: the usual serial "
                        "devices) for its attitude frames, report, exit 0 if found, 1 if not")
            ->expected(0, -1)
            ->type_name("[DEVICE...]");
    }

    Result<CommandLine> parse(std::span<const char* const> argv) {
        std::vector<std::string> reversed;
        for (std::size_t i = argv.size(); i > 1; --i) {
            reversed.emplace_back(argv[i - 1] != nullptr ? argv[i - 1] : "");
        }
        CommandLine line;
        try {
            app_.parse(reversed);
        } catch (const CLI::CallForHelp&) {
            line.help = true;
            return line;
        } catch (const CLI::CallForVersion&) {
            line.version = true;
            return line;
        } catch (const CLI::ParseError& error) {
            return Errors{{args::message_of(error)}};
        }
        if (auto problem = args::leftover_problem(app_); !problem.empty()) {
            return Errors{{problem}};
        }
        set(line.config_path, "--config", config_);
        set(line.device, "--device", device_);
        set(line.socket_path, "--socket", socket_);
        set(line.log_level, "--log-level", log_level_);
        set(line.state_dir, "--state-dir", state_dir_);
        line.simulate = simulate_;
        if (app_.count("--probe") > 0) {
            line.probe.emplace();  // CLI11 gives a bare --probe one empty value
            std::copy_if(probe_.begin(), probe_.end(), std::back_inserter(*line.probe),
                         [](const std::string& device) { return !device.empty(); });
        }
        return line;
    }

    std::string help() const { return app_.help(); }

  private:
    void option(const char* name, std::string& value, std::string description,
                const char* type_name,
                std::function<std::optional<std::string>(std::string_view)> check) {
        app_.add_option(name, value, std::move(description))
            ->type_name(type_name)
            ->check(args::check_with(std::move(check)));
    }

    void set(std::optional<std::string>& target, const char* name, const std::string& value) {
        if (app_.count(name) > 0) {
            target = value;
        }
    }

    std::string config_, device_, socket_, log_level_, state_dir_;
    bool simulate_ = false;
    std::vector<std::string> probe_;
    CLI::App app_;
};

}  // namespace

Result<CommandLine> parse_command_line(std::span<const char* const> args) {
    return Parser().parse(args);
}

std::string usage() {
    return Parser().help();
}

std::string version_text() {
    return fmt::format("gportd {}\n", kVersion);
}

}  // namespace gport::config
