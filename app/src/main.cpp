// gportd: the G-Port gimbal daemon. See `gportd --help` and docs/.
#include <cstdio>
#include <span>

#include "gport/app/config_error_server.hpp"
#include "gport/app/daemon.hpp"
#include "gport/app/probe.hpp"
#include "gport/config/command_line.hpp"
#include "gport/config/loader.hpp"

int main(int argc, char** argv) {
    namespace cfg = gport::config;
    const auto command_line =
        cfg::parse_command_line(std::span<const char* const>(argv, static_cast<std::size_t>(argc)));
    if (!command_line) {
        std::fprintf(stderr, "gportd: %sTry 'gportd --help'.\n",
                     command_line.error().text().c_str());
        return cfg::kExitUsage;
    }
    if (command_line->help) {
        std::fputs(cfg::usage().c_str(), stdout);
        return 0;
    }
    if (command_line->version) {
        std::fputs(cfg::version_text().c_str(), stdout);
        return 0;
    }
    if (command_line->probe) {
        return gport::app::run_probe(*command_line->probe);
    }
    const auto config = cfg::load_config(*command_line);
    if (!config) {
        // Under socket activation, exiting would only make systemd start us
        // again for the waiting client, into the start limit: serve the
        // error instead (docs/operations.md, "A bad configuration under
        // systemd").
        if (auto status =
                gport::app::serve_config_error_if_activated(config.error().text(), *command_line)) {
            return *status;
        }
        std::fprintf(stderr, "gportd: configuration error:\n%s", config.error().text().c_str());
        return cfg::kExitConfig;
    }
    return gport::app::run_daemon(*config, *command_line);
}
