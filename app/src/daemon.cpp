#include "gport/app/daemon.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <csignal>
#include <cstdlib>
#include <exception>
#include <memory>
#include <optional>

#include "gport/app/realtime.hpp"
#include "gport/app/reload.hpp"
#include "gport/base/log_context.hpp"
#include "gport/capture/capture_writer.hpp"
#include "gport/config/advisories.hpp"
#include "gport/config/loader.hpp"
#include "gport/daemon/core.hpp"
#include "gport/ipc/server.hpp"
#include "gport/sim/simulator.hpp"
#include "gport/systemd/activation.hpp"
#include "gport/systemd/logger.hpp"
#include "gport/systemd/notifier.hpp"
#include "gport/systemd/watchdog.hpp"
#include "gport/version.hpp"
#include "hangup.hpp"

namespace gport::app {
namespace {

namespace asio = boost::asio;
using daemon::Core;
using daemon::LinkEvent;

const char* signal_name(int sig) {
    switch (sig) {
        case SIGTERM:
            return "SIGTERM";
        case SIGINT:
            return "SIGINT";
        case SIGQUIT:
            return "SIGQUIT";
        case SIGHUP:
            return "SIGHUP";
        default:
            return "a signal";
    }
}

// What to do when the socket's path is not ours (gportd(8), "EXIT STATUS";
// README.md, "Without root"). The directory suggested is one the user has:
// $XDG_RUNTIME_DIR where the login made one, else (su -, a cron job, no
// systemd user session) their home directory.
std::string socket_access_hint() {
    const char* runtime = std::getenv("XDG_RUNTIME_DIR");
    const bool has_runtime = runtime != nullptr && *runtime == '/';
    const std::string socket =
        has_runtime ? "\"$XDG_RUNTIME_DIR/gportd.sock\"" : "\"$HOME/gportd.sock\"";
    return fmt::format(
        "as a user, serve a socket in a directory you may write, e.g. gportd --simulate "
        "--socket {}{} (and gportctl --socket, or GPORT_SOCKET, for the clients); or run the "
        "installed service (systemctl start gportd) and join the gport group to use its socket",
        socket,
        has_runtime ? ""
                    : " (XDG_RUNTIME_DIR is not set here: a login without a user session, "
                      "such as su -)");
}

// The file a load reads, or none (the built-in defaults): status's config_file.
std::optional<std::string> config_file(const config::CommandLine& command_line) {
    if (command_line.config_path) {
        return *command_line.config_path;
    }
    std::string path = config::default_config_path();
    if (::access(path.c_str(), F_OK) != 0) {
        return std::nullopt;
    }
    return path;
}

// What a reload reads, for its log lines.
std::string config_source(const config::CommandLine& command_line) {
    if (auto file = config_file(command_line)) {
        return *file;
    }
    return "the built-in defaults (" + config::default_config_path() + " does not exist)";
}

std::string status_text(const std::string& device, const LinkEvent& event) {
    if (event.reason == daemon::LinkMonitor::kWaitingForFirstAttitude) {
        return fmt::format("{}: {}", device, event.reason);
    }
    return fmt::format("{}: link {} ({})", device, to_string(event.state), event.reason);
}

// Everything that lives for the daemon's lifetime, in construction order.
class Daemon {
  public:
    Daemon(const config::Config& config, const config::CommandLine& command_line,
           std::shared_ptr<base::LogContext> context, std::shared_ptr<spdlog::logger> log)
        : command_line_(command_line),
          loaded_(config),
          config_(config),
          context_(std::move(context)),
          log_(std::move(log)),
          notifier_(log_),
          watchdog_(io_, notifier_),
          hangup_(HangupRule::at_start()),
          signals_(io_, SIGINT, SIGTERM, SIGQUIT) {
        signals_.add(SIGHUP);
    }

    int run() {
        if (config_.simulate) {
            start_simulator();
        }
        context_->set(base::kFieldDevice, config_.serial.device);
        core_.emplace(io_, config_, log_);
        core_->add_link_listener([this](const LinkEvent& e) { on_link(e); });
        if (!start_server()) {
            return kExitFailure;
        }
        start_captures();
        core_->start();
        notifier_.ready();
        if (auto interval = watchdog_.start()) {
            log_->info("watchdog enabled: pinging every {} ms", interval->count() / 1000);
        }
        wait_for_signal();
        if (hangup_.watches_terminal()) {
            log_->info(
                "started from a terminal: gportd ends when it hangs up (closing it, logging "
                "out); `kill -HUP` while it is open reloads the configuration");
        }
        log_->info("gportd {} ready", kVersion);
        io_.run();
        if (capture_writer_ != nullptr) {  // every client gone: no capture after this
            capture_writer_->finish(server_->captures().next_index());
        }
        log_->info("gportd stopped");
        return 0;
    }

  private:
    void start_simulator() {
        simulator_.emplace(io_, sim::SimOptions{});
        config_.serial.device = simulator_->device_path();
        log_->info("--simulate: simulated gimbal on {}", config_.serial.device);
    }

    bool start_server() {
        std::optional<int> activated;
        try {
            activated = systemd::activated_socket_fd();
            server_.emplace(io_, *core_, config_.socket, log_, activated);
            server_->set_config_file(config_file(command_line_));
            server_->start();
        } catch (const systemd::ActivationError& e) {
            log_->critical("socket activation: {}", e.what());
            exit_status_ = kExitConfig;
            return false;
        } catch (const ipc::SocketAccessError& e) {
            log_->critical("{}", e.what());
            log_->critical("{}", socket_access_hint());
            return false;
        } catch (const std::exception& e) {
            log_->critical("{}", e.what());
            return false;
        }
        if (activated) {
            log_->info("serving clients on the socket passed by systemd");
        }
        return true;
    }

    // The capture log's directory: --state-dir or captures.dir, else the
    // unit's StateDirectory= ($STATE_DIRECTORY, its first entry).
    std::string state_dir() const {
        if (!config_.captures.dir.empty()) {
            return config_.captures.dir;
        }
        const char* systemd_dir = std::getenv("STATE_DIRECTORY");
        const std::string dirs = systemd_dir != nullptr ? systemd_dir : "";
        return dirs.substr(0, dirs.find(':'));
    }

    // Checks the state directory, restores the indexes and the newest
    // captures from the files, then hands the log its writer; before
    // io_.run(), so before any capture.
    void start_captures() {
        const auto dir = state_dir();
        if (dir.empty() || dir.front() != '/') {
            const auto level = config_.simulate ? spdlog::level::info : spdlog::level::warn;
            log_->log(level,
                      "capture log kept in memory only (its indexes restart at 1): no state "
                      "directory (--state-dir, captures.dir or the unit's StateDirectory=)");
            return;
        }
        const capture::CaptureFiles files{dir, config_.captures.max_file_bytes,
                                          config_.captures.keep_files};
        auto opened = capture::open_capture_log(files, server_->captures(), log_);
        capture_sink_ = std::move(opened.sink);
        capture_writer_ = opened.writer;
        server_->captures().set_sink(capture_sink_.get());
    }

    void on_link(const LinkEvent& event) {
        context_->set(base::kFieldLink, std::string(to_string(event.state)));
        notifier_.status(status_text(config_.serial.device, event));
    }

    // SIGHUP reloads and waits again, unless it is the hang-up of the
    // terminal gportd was started from (hangup.hpp); the others stop the
    // daemon. The set stays installed while stopping, so a second signal
    // cannot kill the process before the gimbal heard its zero speed.
    void wait_for_signal() {
        signals_.async_wait([this](boost::system::error_code ec, int sig) {
            if (ec) {
                return;
            }
            if (sig == SIGHUP && hangup_.is_hangup()) {
                if (!stopping_) {
                    log_->info("the terminal gportd was started from hung up");
                    stop(sig);
                }
            } else if (sig == SIGHUP) {
                reload();
                wait_for_signal();
            } else if (!stopping_) {
                stop(sig);
            }
        });
    }

    void reload() {
        if (stopping_) {
            return;
        }
        notifier_.reloading();
        const auto path = config_source(command_line_);
        auto next = config::load_config(command_line_);
        if (!next) {
            for (const auto& message : next.error().messages) {
                log_->error("reload: {}", message);
            }
            log_->error(
                "configuration not reloaded: {} error(s) in {}; still running on the "
                "previous configuration",
                next.error().messages.size(), path);
        } else {
            apply(path, plan_reload(loaded_, *next));
        }
        notifier_.ready();
    }

    void apply(const std::string& path, ReloadPlan plan) {
        log_->set_level(spdlog::level::from_str(plan.in_effect.log.level));
        core_->reload(plan.in_effect);
        for (const auto& key : plan.applied) {
            log_->info("reload: {} changed; applied", key);
        }
        for (const auto& key : plan.need_restart) {
            log_->warn("reload: {} changed; it needs a restart to take effect", key);
        }
        for (const auto& line : config::advisories(plan.in_effect)) {
            log_->warn("reload: {}", line);
        }
        log_->info("reloaded configuration from {}: {} keys applied, {} need a restart", path,
                   plan.applied.size(), plan.need_restart.size());
        loaded_ = std::move(plan.in_effect);
    }

    // Motion is stopped on the wire first, then clients are closed, so the
    // last thing the gimbal hears from us is a zero speed.
    void stop(int sig) {
        stopping_ = true;
        log_->info("stopping on {}", signal_name(sig));
        notifier_.stopping();
        core_->shutdown([this] {
            server_->close();
            watchdog_.stop();
            if (simulator_) {
                simulator_->stop();
            }
        });
    }

  public:
    int exit_status() const { return exit_status_; }

  private:
    config::CommandLine command_line_;  // re-read on SIGHUP, with the same overrides
    config::Config loaded_;             // as loaded (and reloaded), before --simulate
    config::Config config_;
    std::shared_ptr<base::LogContext> context_;
    std::shared_ptr<spdlog::logger> log_;
    asio::io_context io_{1};  // one thread: Asio may skip its locking
    systemd::Notifier notifier_;
    systemd::WatchdogDriver watchdog_;
    HangupRule hangup_;  // read before signals_ installs its handlers
    asio::signal_set signals_;
    std::optional<sim::PtySimulator> simulator_;
    std::optional<Core> core_;
    std::unique_ptr<capture::CaptureSink> capture_sink_;  // outlives the server, its user
    capture::CaptureWriter* capture_writer_ = nullptr;    // the sink, when it writes files
    std::optional<ipc::Server> server_;
    int exit_status_ = kExitFailure;
    bool stopping_ = false;
};

}  // namespace

int run_daemon(const config::Config& config, const config::CommandLine& command_line) {
    std::signal(SIGPIPE, SIG_IGN);
    // The logger sends the process's context: the fields the app sets here
    // (device, link) and the client fields ipc and the core scope around
    // what a client causes. Non-owning: the context outlives everything.
    std::shared_ptr<base::LogContext> context(std::shared_ptr<void>(),
                                              &base::process_log_context());
    systemd::LoggerOptions options;
    options.level = spdlog::level::from_str(config.log.level);
    auto log = systemd::make_logger(options, context);
    spdlog::set_default_logger(log);
    const auto realtime = apply_realtime(config.realtime);
    for (const auto& line : realtime.applied) {
        log->info("{}", line);
    }
    for (const auto& line : realtime.warnings) {
        log->warn("{}", line);
    }
    for (const auto& line : config::advisories(config)) {
        log->warn("{}", line);
    }
    try {
        Daemon daemon(config, command_line, context, log);
        const int status = daemon.run();
        return status == 0 ? 0 : daemon.exit_status();
    } catch (const std::exception& e) {
        log->critical("fatal: {}", e.what());
        return kExitFailure;
    }
}

}  // namespace gport::app
