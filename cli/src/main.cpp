// gportctl: command-line client of gportd (see `gportctl --help`).
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <iostream>

#include "gport/cli/run.hpp"
#include "gport/contract/names.hpp"

namespace {

volatile std::sig_atomic_t g_interrupted = 0;

void on_signal(int) {
    g_interrupted = 1;
}

// Without SA_RESTART, so that a blocking poll() returns at once.
void catch_signal(int signal) {
    struct sigaction action {};
    action.sa_handler = on_signal;
    sigemptyset(&action.sa_mask);
    ::sigaction(signal, &action, nullptr);
}

}  // namespace

int main(int argc, char** argv) {
    catch_signal(SIGINT);
    catch_signal(SIGTERM);
    std::signal(SIGPIPE, SIG_IGN);
    std::vector<std::string> args(argv + 1, argv + argc);
    return gport::cli::main_with(args, std::getenv(gport::contract::kSocketEnv), std::cout,
                                 std::cerr, [] { return g_interrupted != 0; },
                                 {::isatty(STDOUT_FILENO) == 1, ::isatty(STDERR_FILENO) == 1});
}
