// End-to-end harness: the real gport-sim and gportd binaries, started as
// child processes on a temporary directory, talking over a pty and a socket.
#pragma once

#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "client.hpp"
#include "process.hpp"

namespace gport::testing {

// gport-sim with --trace under a symlink; its trace lines are kept.
// `wrapper` runs it under another command, e.g. {"/usr/bin/setpriv", ...} (an absolute path).
class SimProcess {
  public:
    SimProcess(const TempDir& dir, std::vector<std::string> extra = {},
               std::vector<std::string> wrapper = {})
        : link_(dir.file("gimbal")) {
        std::vector<std::string> argv = std::move(wrapper);
        for (std::string arg : {GPORT_SIM_PATH, "--link", link_.c_str(), "--trace"}) {
            argv.push_back(std::move(arg));
        }
        argv.insert(argv.end(), extra.begin(), extra.end());
        process_ = std::make_unique<Process>(argv);
        process_->next_line();  // the slave path
    }
    const std::string& link() const { return link_; }
    Process& process() { return *process_; }

    // Waits for a trace line of a speed frame equal to [roll, pitch, yaw].
    bool wait_speed(const Json& speed, std::chrono::milliseconds timeout = 10s) {
        return process_
            ->wait_line(
                [&](const std::string& line) {
                    auto j = Json::parse(line, nullptr, false);
                    return j.is_object() && j.value("mode", "") == "speed" && j["speed"] == speed;
                },
                timeout)
            .has_value();
    }

  private:
    std::string link_;
    std::unique_ptr<Process> process_;
};

// Whether `text` holds `part` (a log line, a screen).
inline bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

// Waits until the daemon reports its link to the gimbal up.
inline bool link_up(Client& client) {
    return eventually([&] { return client.call("status")["result"]["link"]["state"] == "up"; });
}

// A config file with fast timings for tests, and the camera limit at its
// highest (tests take photos back to back) unless `extra` has a "camera"
// section of its own (a "link" section of its own replaces the timings'
// too).
inline std::string write_test_config(const TempDir& dir, const std::string& extra = "") {
    const std::string path = dir.file("gportd.json");
    const bool own_camera = extra.find("\"camera\"") != std::string::npos;
    const bool own_link = extra.find("\"link\"") != std::string::npos;
    std::ofstream(path) << "{\n  // test timings\n"
                        << (own_link ? ""
                                     : "  \"link\": {\"stale_ms\": 300, \"reconnect_initial_ms\": "
                                       "50, \"reconnect_max_ms\": 200},\n")
                        << "  \"requests\": {\"timeout_ms\": 200, \"retries\": 1}"
                        << (own_camera ? "" : ",\n  \"camera\": {\"max_commands_per_s\": 1000}")
                        << (extra.empty() ? "" : ",\n  " + extra) << "\n}\n";
    return path;
}

// gportd on a device (or --simulate), with a socket in dir.
class DaemonProcess {
  public:
    // `config_extra`: more sections for the config file, as write_test_config.
    // `wrapper` runs it under another command, as for SimProcess.
    DaemonProcess(const TempDir& dir, std::vector<std::string> args,
                  std::vector<std::string> env = {}, const std::string& config_extra = "",
                  std::vector<std::string> wrapper = {})
        : socket_(dir.file("gportd.sock")) {
        std::vector<std::string> argv = std::move(wrapper);
        for (std::string arg : {std::string(GPORTD_PATH), std::string("--config"),
                                write_test_config(dir, config_extra), std::string("--socket"),
                                socket_, std::string("--log-level"), std::string("warn")}) {
            argv.push_back(std::move(arg));
        }
        argv.insert(argv.end(), args.begin(), args.end());
        process_ = std::make_unique<Process>(argv, env);
    }
    const std::string& socket() const { return socket_; }
    Process& process() { return *process_; }

  private:
    std::string socket_;
    std::unique_ptr<Process> process_;
};

}  // namespace gport::testing
