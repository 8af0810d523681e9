// The subcommands' flows: one call and print; watch (subscribe, then print
// events); speed (keep the motion alive while gportctl runs).
#include "gport/cli/run.hpp"

#include <fmt/format.h>

#include <thread>

#include "gport/cli/monitor.hpp"
#include "gport/cli/output.hpp"
#include "gport/client/connection.hpp"
#include "gport/client/error.hpp"

namespace gport::cli {
namespace {

using client::Connection;
using nlohmann::json;
using namespace std::chrono_literals;

// Without --for, speed is re-sent this often for this long: if gportctl
// dies or hangs, the gimbal stops within the duration.
constexpr auto kResendEvery = 200ms;
constexpr auto kResendDuration = 500ms;

class Runner {
  public:
    Runner(const Invocation& inv, Connection& conn, std::ostream& out, std::ostream& err)
        : inv_(inv), conn_(conn), out_(out), err_(err) {}

    int dispatch() {
        if (inv_.command == "watch") {
            return watch();
        }
        if (inv_.command == "speed") {
            return inv_.duration ? speed_for() : speed_until_interrupted();
        }
        json result;
        const int status = call(inv_.method, inv_.params, result);
        if (status != kExitOk) {
            return status;
        }
        print(result);
        return inv_.wait && !reached(result) ? kExitNotReached : kExitOk;
    }

  private:
    // Calls a method; prints the error for the user.
    int call(const std::string& method, const json& params, json& result) {
        auto reply = conn_.call(method, params, [this](const json& n) { notification(n); });
        if (!reply) {
            if (conn_.interrupted()) {
                return kExitInterrupted;
            }
            err_ << "gportctl: the daemon closed the connection\n";
            return kExitUnavailable;
        }
        if (reply->contains("error")) {
            err_ << "gportctl: " << format_error((*reply)["error"]) << "\n";
            return kExitError;
        }
        result = reply->value("result", json());
        return kExitOk;
    }

    void print(const json& result) {
        out_ << (inv_.json ? result.dump() + "\n" : format_result(inv_.command, result));
        out_.flush();
    }

    void notification(const json& message) {
        if (inv_.command != "watch") {
            return;
        }
        out_ << (inv_.json ? message.dump() + "\n" : format_notification(message));
        out_.flush();
    }

    int watch() {
        json result;
        if (const int status = call("subscribe", inv_.params, result); status != kExitOk) {
            return status;
        }
        if (!inv_.json) {
            print(result);
        }
        json message;
        while (true) {
            switch (conn_.read(message)) {
                case Connection::ReadStatus::kMessage:
                    if (!message.contains("id")) {
                        notification(message);
                    }
                    break;
                case Connection::ReadStatus::kInterrupted:
                    return kExitOk;
                case Connection::ReadStatus::kClosed:
                case Connection::ReadStatus::kTimeout:
                    err_ << "gportctl: the daemon closed the connection\n";
                    return kExitUnavailable;
            }
        }
    }

    // Sends stop on the way out, ignoring the interruption that asked for it.
    int stop_and_exit() {
        conn_.interrupted = [] { return false; };
        json ignored;
        const int status = call("stop", json::object(), ignored);
        if (status == kExitOk && !inv_.json) {
            out_ << "stopped\n";
        }
        return status;
    }

    // The daemon keeps the motion alive; we stay connected until it ends
    // (it would stop the motion of a client that disconnects).
    int speed_for() {
        json result;
        if (const int status = call("subscribe", {{"topics", {"motion"}}}, result);
            status != kExitOk) {
            return status;
        }
        if (const int status = call("speed", inv_.params, result); status != kExitOk) {
            return status;
        }
        print(result);
        const auto deadline = std::chrono::steady_clock::now() + *inv_.duration + 2s;
        json message;
        while (std::chrono::steady_clock::now() < deadline) {
            const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                deadline - std::chrono::steady_clock::now());
            switch (conn_.read(message, left)) {
                case Connection::ReadStatus::kMessage:
                    if (motion_over(message)) {
                        return kExitOk;
                    }
                    break;
                case Connection::ReadStatus::kInterrupted:
                    return stop_and_exit();
                case Connection::ReadStatus::kClosed:
                    err_ << "gportctl: the daemon closed the connection\n";
                    return kExitUnavailable;
                case Connection::ReadStatus::kTimeout:
                    return kExitOk;
            }
        }
        return kExitOk;
    }

    // angle/center --wait: the reply came when the motion ended.
    static bool reached(const json& result) {
        const auto ended = result.value("ended", json::object());
        return ended.is_object() && ended.value("reason", "") == "reached";
    }

    static bool motion_over(const json& message) {
        if (message.value("method", "") != "motion") {
            return false;
        }
        const auto change = message["params"].value("change", "");
        return change == "ended" || change == "replaced";
    }

    int speed_until_interrupted() {
        json params = inv_.params;
        params["duration_ms"] = std::chrono::milliseconds(kResendDuration).count();
        json result;
        if (const int status = call("speed", params, result); status != kExitOk) {
            return status;
        }
        if (!inv_.json) {
            out_ << "moving; Ctrl-C to stop\n";
            out_.flush();
        }
        while (true) {
            const auto next = std::chrono::steady_clock::now() + kResendEvery;
            json message;
            while (conn_.read(message, std::chrono::duration_cast<std::chrono::milliseconds>(
                                           next - std::chrono::steady_clock::now())) ==
                   Connection::ReadStatus::kMessage) {
            }
            if (conn_.interrupted()) {
                return stop_and_exit();
            }
            if (const int status = call("speed", params, result); status != kExitOk) {
                return conn_.interrupted() ? stop_and_exit() : status;
            }
        }
    }

    const Invocation& inv_;
    Connection& conn_;
    std::ostream& out_;
    std::ostream& err_;
};

}  // namespace

int run(const Invocation& invocation, std::ostream& out, std::ostream& err,
        std::function<bool()> interrupted) {
    if (invocation.command == "monitor") {
        return run_monitor(invocation.monitor, out, err, interrupted);
    }
    std::optional<Connection> opened;
    try {
        opened.emplace(Connection::open(invocation.socket));
    } catch (const client::Error& e) {
        err << "gportctl: " << e.what() << "\n";
        return kExitUnavailable;
    }
    auto& conn = *opened;
    conn.interrupted = std::move(interrupted);
    return Runner(invocation, conn, out, err).dispatch();
}

int main_with(const std::vector<std::string>& args, const char* env_socket, std::ostream& out,
              std::ostream& err, std::function<bool()> interrupted) {
    auto parsed = parse_args(args, env_socket);
    if (!parsed) {
        err << "gportctl: " << parsed.error().message << "\nTry 'gportctl --help'.\n";
        return kExitUsage;
    }
    const auto& invocation = *parsed;
    if (invocation.help) {
        out << usage(invocation.command);
        return kExitOk;
    }
    return run(invocation, out, err, std::move(interrupted));
}

}  // namespace gport::cli
