// gportctl's one-call commands and its entry points (runner.hpp).
#include "gport/cli/run.hpp"

#include <fmt/format.h>

#include "geotag_dir.hpp"
#include "gport/cli/monitor.hpp"
#include "gport/cli/output.hpp"
#include "gport/cli/printable.hpp"
#include "gport/contract/errors.hpp"
#include "gport/contract/names.hpp"
#include "runner.hpp"
#include "wait.hpp"

namespace gport::cli {

using nlohmann::json;

Runner::Runner(const Invocation& inv, client::Client& gportd, std::ostream& out, std::ostream& err,
               std::function<bool()> interrupted, Terminals terminals)
    : inv_(inv),
      gportd_(gportd),
      out_(out),
      err_(err),
      interrupted_(std::move(interrupted)),
      terminals_(terminals) {
    gportd_.set_interrupt(interrupted_);
    gportd_.on_notification_json(
        [this](const std::string& text) { notification(json::parse(text, nullptr, false)); });
}

int Runner::dispatch() {
    if (inv_.command == "watch") {
        return watch();
    }
    if (inv_.command == "speed") {
        return inv_.duration ? speed_for() : speed_until_interrupted();
    }
    if (inv_.command == "call") {
        return call_any();
    }
    if (inv_.command == "captures") {
        return captures();
    }
    const CallFn call_fn = [this](auto& m, auto& p, auto& r) { return call(m, p, r); };
    if (inv_.command == "geotag") {
        return geotag_dir(inv_, call_fn, out_, err_);
    }
    if (inv_.command == "wait") {
        return wait_link(inv_, gportd_, call_fn, interrupted_, out_, err_);
    }
    json result;
    const int status = call(inv_.method, inv_.params, result);
    if (status != kExitOk) {
        return status;
    }
    if (const int printed = print(result); printed != kExitOk) {
        return printed;
    }
    if (inv_.command == "status" && !link_up(result.value("link", json()))) {
        return kExitLinkNotUp;  // a health check: printed as ever, but not 0
    }
    const auto ended = result.value("ended", json::object());
    const bool reached = ended.is_object() && ended.value("reason", "") == "reached";
    return inv_.wait && !reached ? kExitNotReached : kExitOk;  // angle/center --wait
}

// gportctl call: the result as one line of JSON, or with --raw the whole
// response (an error's too, besides the message on stderr).
int Runner::call_any() {
    json result;
    json response;
    const int status = call(inv_.method, inv_.params, result, &response);
    if (inv_.raw && !response.is_null()) {
        out_ << json_line(response) << "\n";
    } else if (status == kExitOk) {
        out_ << json_line(result) << "\n";
    }
    out_.flush();
    return status;
}

// Calls a method; prints the error for the user. `response`, if given,
// receives the whole response.
int Runner::call(const std::string& method, const json& params, json& result, json* response) {
    json reply;
    try {
        reply = json::parse(
            gportd_.call_json_response(method, params.is_null() ? std::string() : params.dump()));
    } catch (const client::Error& e) {
        return failed(e);
    }
    if (response != nullptr) {
        *response = reply;
    }
    if (reply.contains("error")) {
        return refused(reply["error"], params);
    }
    result = reply.value("result", json());
    return kExitOk;
}

// gportd's refusal: a usage error when it names an option typed, else in
// the command line's words (`call` speaks the API's).
int Runner::refused(const json& error, const json& params) {
    if (auto usage = option_refusal(error, params)) {
        err_ << "gportctl: " << *usage << "\nTry 'gportctl " << inv_.command << " --help'.\n";
        return kExitUsage;
    }
    err_ << "gportctl: " << format_error(inv_.command == "call" ? error : cli_wording(error))
         << "\n";
    return kExitError;
}

// The library's errors: Ctrl-C, the connection gone (why, when the library
// ended it: a line over its limits, a request gportd did not read), no reply
// within the call timeout, or a refusal of a typed call (watch
// --shared-memory).
int Runner::failed(const client::Error& error) {
    if (error.is(client::ErrorCode::kInterrupted)) {
        return kExitInterrupted;
    }
    const bool library = error.transport() || error.is(client::ErrorCode::kTimeout) ||
                         error.is(client::ErrorCode::kBadReply);
    err_ << "gportctl: " << (library ? printable(error.message()) : format_error(error)) << "\n";
    return library ? kExitUnavailable : kExitError;
}

// gportd's keepalive.max_duration_ms is known only to the daemon: its
// refusal of a duration or lease is a usage error naming the option typed.
// gportd says "duration_ms must be an integer from 1 to 60000
// (keepalive.max_duration_ms)"; before 0.1.x's issue 22 its core said
// "duration_ms = 120000 is out of range; allowed 1 to 60000".
std::optional<std::string> Runner::option_refusal(const json& error, const json& params) {
    const std::string message = error.value("message", "");
    if (error.value("code", 0) != contract::rpc_error::kInvalidParams) {
        return std::nullopt;
    }
    for (const auto& [param, option] :
         {std::pair{"duration_ms", "--for"}, std::pair{"lease_ms", "--lease"}}) {
        if (!message.starts_with(param) || !params.contains(param)) {
            continue;
        }
        std::string range;
        if (const auto from = message.find(" must be an integer from ");
            from != std::string::npos) {
            range = message.substr(from + 25);
            range = range.substr(0, range.find(" ("));
        } else if (const auto allowed = message.find("; allowed "); allowed != std::string::npos) {
            range = message.substr(allowed + 10);
        } else {
            continue;
        }
        return fmt::format(
            "{}: {} ms is longer than gportd allows: {} ms (its keepalive.max_duration_ms)", option,
            params[param].dump(), printable(range));
    }
    return std::nullopt;
}

int Runner::print(const json& result) {
    try {
        out_ << (inv_.json ? json_line(result) + "\n" : format_result(inv_.command, result));
    } catch (const client::Error& e) {
        return failed(e);
    }
    out_.flush();
    return kExitOk;
}

// Sends stop on the way out, ignoring the interruption that asked for it.
int Runner::stop_and_exit() {
    gportd_.set_interrupt({});
    json ignored;
    const int status = call(contract::method::kStop, json::object(), ignored);
    if (status == kExitOk && !inv_.json) {
        out_ << "stopped\n";
    }
    return status;
}

int run(const Invocation& invocation, std::ostream& out, std::ostream& err,
        std::function<bool()> interrupted, Terminals terminals) {
    if (invocation.command == "monitor") {
        return run_monitor(invocation.monitor, out, err, interrupted);
    }
    if (invocation.command == "geotag" && !invocation.captures_files.empty()) {
        // From capture log files: no daemon to ask.
        return geotag_dir(
            invocation, [](auto&, auto&, auto&) { return kExitUnavailable; }, out, err);
    }
    std::optional<client::Client> gportd;
    try {
        gportd.emplace(client::Client::connect(invocation.socket));
    } catch (const client::Error& e) {
        err << "gportctl: " << printable(e.message()) << "\n";
        return kExitUnavailable;
    }
    return Runner(invocation, *gportd, out, err, std::move(interrupted), terminals).dispatch();
}

int main_with(const std::vector<std::string>& args, const char* env_socket, std::ostream& out,
              std::ostream& err, std::function<bool()> interrupted, Terminals terminals) {
    auto parsed = parse_args(args, env_socket);
    if (!parsed) {
        const auto& command = parsed.error().command;
        err << "gportctl: " << parsed.error().message << "\nTry 'gportctl "
            << (command.empty() || command == "help" ? "" : command + " ") << "--help'.\n";
        return kExitUsage;
    }
    const auto& invocation = *parsed;
    if (invocation.help) {
        out << invocation.text;
        return kExitOk;
    }
    return run(invocation, out, err, std::move(interrupted), terminals);
}

}  // namespace gport::cli
