// gport-mavlink: the G-Port, served by gportd, as a MAVLink gimbal v2 device.
// See `gport-mavlink --help` and docs/mavlink.md.
#include <spdlog/spdlog.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "bridge.hpp"
#include "gport/base/exit_status.hpp"
#include "gport/client/client.hpp"
#include "gport/mavlink/bridge/signing_files.hpp"
#include "gport/systemd/logger.hpp"

namespace {

namespace bridge = gport::mavlink::bridge;

std::string env(const char* name) {
    const char* value = std::getenv(name);
    return value != nullptr ? value : "";
}

// Native journald entries (with priorities) when stderr is the journal,
// "time [level] text" lines on stderr otherwise: gportd's logger.
void set_up_logging(const std::string& level) {
    gport::systemd::LoggerOptions options;
    options.name = "gport-mavlink";
    options.level = spdlog::level::from_str(level);
    spdlog::set_default_logger(gport::systemd::make_logger(options, nullptr));
}

// The signing session of --signing-key, or null; nullopt (after logging
// why) when the key or the state directory is unusable.
std::optional<std::unique_ptr<bridge::SigningSession>> open_signing(const bridge::Options& options,
                                                                    bridge::Logbook& log) {
    if (options.signing_key.empty()) {
        return std::unique_ptr<bridge::SigningSession>();
    }
    auto key = bridge::load_signing_key(options.signing_key);
    if (!key) {
        spdlog::critical("gport-mavlink: {}", key.error().message);
        return std::nullopt;
    }
    auto session = bridge::SigningSession::open(std::move(*key), options.state_dir, log);
    if (!session) {
        spdlog::critical("gport-mavlink: signing timestamp: {}", session.error().message);
        return std::nullopt;
    }
    return std::move(*session);
}

}  // namespace

int main(int argc, char** argv) {
    const auto parsed =
        bridge::parse_options(std::vector<std::string>(argv, argv + argc),
                              {env(gport::client::Client::kSocketEnv), env("STATE_DIRECTORY")});
    if (!parsed.options) {
        std::fputs(parsed.text.c_str(), parsed.exit_code == 0 ? stdout : stderr);
        return parsed.exit_code;
    }
    const auto& options = *parsed.options;
    set_up_logging(options.log_level);
    std::signal(SIGPIPE, SIG_IGN);
    bridge::Logbook log;
    auto signing = open_signing(options, log);
    if (!signing) {
        return gport::kExitConfig;
    }
    try {
        boost::asio::io_context io;
        bridge::Bridge gimbal(io, options, std::move(*signing), log);
        gimbal.start();
        boost::asio::signal_set signals(io, SIGINT, SIGTERM);
        signals.async_wait([&](boost::system::error_code, int signal) {
            spdlog::info("gport-mavlink: signal {}, exiting", signal);
            io.stop();
        });
        io.run();
        gimbal.finish();
    } catch (const std::exception& e) {
        // The Bridge, and with it the signing session, was destroyed on the
        // way here: its destructor wrote the exact current timestamp.
        spdlog::critical("gport-mavlink: {}", e.what());
        return gport::kExitOsError;
    }
    return gport::kExitOk;
}
