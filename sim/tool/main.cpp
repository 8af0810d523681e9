// gport-sim: a thin wrapper over PtySimulator (see gport/sim/simulator.hpp).
#include <fmt/format.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <csignal>
#include <cstdio>
#include <stdexcept>
#include <string_view>
#include <system_error>
#include <vector>

#include "gport/sim/command_line.hpp"
#include "gport/sim/simulator.hpp"

namespace {

using namespace gport::sim;

// Each trace line is written and flushed whole, so a reader never sees half
// a line. A closed stdout is ignored: the simulator keeps serving.
void print_line(const std::string& line) {
    std::fputs(line.c_str(), stdout);
    std::fputc('\n', stdout);
    std::fflush(stdout);
}

// SIGUSR1 stalls the gimbal's side of the line, SIGUSR2 lets it drain again.
void watch_stall_signals(boost::asio::signal_set& signals, PtySimulator& sim) {
    signals.async_wait([&signals, &sim](const boost::system::error_code& ec, int number) {
        if (ec || sim.stopped()) {
            return;
        }
        if (number == SIGUSR1) {
            sim.pause_reading();
        } else {
            sim.resume_reading();
        }
        watch_stall_signals(signals, sim);
    });
}

int run(CommandLine cl) {
    if (cl.trace) {
        cl.options.trace = print_line;
    }
    boost::asio::io_context io;
    PtySimulator sim(io, std::move(cl.options));
    print_line(sim.slave_path());

    boost::asio::signal_set signals_stall(io, SIGUSR1, SIGUSR2);
    boost::asio::signal_set signals(io, SIGINT, SIGTERM);
    signals.async_wait([&](const boost::system::error_code& ec, int) {
        if (!ec) {
            sim.stop();
            signals_stall.cancel();
        }
    });
    watch_stall_signals(signals_stall, sim);
    io.run();
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    std::signal(SIGPIPE, SIG_IGN);  // a closed stdout must not kill the simulator
    const std::vector<std::string_view> args(argv + 1, argv + argc);
    auto parsed = parse_command_line(args);
    if (!parsed) {
        fmt::print(stderr, "gport-sim: {}\nTry 'gport-sim --help'.\n", parsed.error().message);
        return kExitUsage;
    }
    if (parsed->help) {
        fmt::print("{}", help_text());
        return 0;
    }
    if (parsed->version) {
        fmt::print("{}", version_text());
        return 0;
    }
    try {
        return run(std::move(parsed).value());
    } catch (const std::system_error& e) {
        fmt::print(stderr, "gport-sim: {}\n", e.what());
        return kExitOsError;
    } catch (const std::runtime_error& e) {
        fmt::print(stderr, "gport-sim: {}\n", e.what());
        return kExitNoInput;
    }
}
