// gport-mavlink: the G-Port, served by gportd, as a MAVLink gimbal v2 device.
// See `gport-mavlink --help` and docs/mavlink.md.
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "bridge.hpp"
#include "gport/base/exit_status.hpp"

int main(int argc, char** argv) {
    namespace bridge = gport::mavlink::bridge;
    const char* env = std::getenv("GPORT_SOCKET");
    const auto parsed = bridge::parse_options(std::vector<std::string>(argv, argv + argc),
                                              env != nullptr ? env : "");
    if (!parsed.options) {
        std::fputs(parsed.text.c_str(), parsed.exit_code == 0 ? stdout : stderr);
        return parsed.exit_code;
    }
    const auto& options = *parsed.options;
    spdlog::set_default_logger(spdlog::stderr_color_mt("gport-mavlink"));
    spdlog::set_pattern("%l: %v");
    spdlog::set_level(spdlog::level::from_str(options.log_level));
    try {
        boost::asio::io_context io;
        bridge::Bridge gimbal(io, options);
        gimbal.start();
        boost::asio::signal_set signals(io, SIGINT, SIGTERM);
        signals.async_wait([&](boost::system::error_code, int signal) {
            spdlog::info("gport-mavlink: signal {}, exiting", signal);
            io.stop();
        });
        io.run();
    } catch (const std::exception& e) {
        spdlog::critical("gport-mavlink: {}", e.what());
        return gport::kExitOsError;
    }
    return gport::kExitOk;
}
