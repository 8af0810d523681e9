#include "daemon_process.hpp"

#include <unistd.h>

#include <chrono>
#include <fstream>
#include <stdexcept>

namespace gport::bench {

void write_daemon_config(const DaemonOptions& options) {
    std::ofstream out(options.config_path);
    out << "// Written by the gportd benchmark for one run; see docs/performance.md.\n"
        << "{\n"
        << "    // Room for the 1000-subscriber case plus the flooding and control clients,\n"
        << "    // all of them under the benchmark's one uid.\n"
        << "    \"socket\": {\"max_clients\": " << options.max_clients
        << ", \"max_clients_per_uid\": " << options.max_clients << ", \"mode\": \""
        << options.socket_mode << "\"";
    if (options.max_requests_per_s > 0) {
        // The flood cells measure the loop, not the per-client rate limit.
        out << ",\n               \"max_requests_per_s\": " << options.max_requests_per_s;
    }
    out << "},\n"
        << "    // One speed command lasts the whole run, so keepalive ticks are never reset.\n"
        << "    \"keepalive\": {\"max_duration_ms\": " << options.max_duration_ms << "},\n"
        << "    \"log\": {\"level\": \"" << options.log_level << "\"}";
    if (options.realtime_priority > 0) {  // only when asked: older gportd builds lack the key
        out << ",\n    \"realtime\": {\"priority\": " << options.realtime_priority
            << ", \"lock_memory\": true}";
    }
    if (!options.extra_config.empty()) {
        out << ",\n    " << options.extra_config;
    }
    out << "\n"
        << "}\n";
    if (!out) {
        throw std::runtime_error("cannot write the daemon config " + options.config_path);
    }
}

namespace {

// The program's path checked, then its argv: a clear error instead of a
// child exiting 127.
std::vector<std::string> executable(std::vector<std::string> argv, const std::string& hint) {
    if (argv.empty() || ::access(argv[0].c_str(), X_OK) != 0) {
        throw std::runtime_error("not executable: " + (argv.empty() ? std::string() : argv[0]) +
                                 hint);
    }
    return argv;
}

std::vector<std::string> daemon_argv(const DaemonOptions& options) {
    write_daemon_config(options);
    std::vector<std::string> argv = {options.binary, "--config", options.config_path, "--device",
                                     options.device, "--socket", options.socket};
    argv.insert(argv.end(), options.extra_args.begin(), options.extra_args.end());
    return executable(std::move(argv), " (pass --gportd PATH)");
}

testing::Launch to_log(const std::string& log_path, bool realtime) {
    testing::Launch launch;
    launch.output = testing::Launch::Output::kFile;
    launch.file = log_path;
    launch.realtime = realtime;
    return launch;
}

}  // namespace

DaemonProcess::DaemonProcess(const DaemonOptions& options)
    : process_(daemon_argv(options), to_log(options.log_path, options.realtime)) {}

DaemonProcess::DaemonProcess(const std::vector<std::string>& argv, const std::string& log_path)
    : process_(executable(argv, ""), to_log(log_path, false)) {}

DaemonProcess::~DaemonProcess() {
    terminate(2000);
}

int DaemonProcess::terminate(int timeout_ms) {
    return process_.terminate(std::chrono::milliseconds(timeout_ms));
}

}  // namespace gport::bench
