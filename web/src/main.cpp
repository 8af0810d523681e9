// gport-web: the gimbal in a browser (docs/web.md).
#include <spdlog/spdlog.h>

#include <string>
#include <vector>

#include "gport/systemd/logger.hpp"
#include "gport/web/run.hpp"

int main(int argc, char** argv) {
    // gportd's and gport-mavlink's logger: native journald entries (with
    // priorities) under systemd, "time [level] text" on stderr otherwise.
    // What a user or a script reads on stdout (where it serves, the login
    // link) stays plain lines there (docs/web.md, "Running it").
    gport::systemd::LoggerOptions logging;
    logging.name = "gport-web";
    spdlog::set_default_logger(gport::systemd::make_logger(logging, nullptr));
    const std::vector<std::string> args(argv + 1, argv + argc);
    return gport::web::run(args);
}
