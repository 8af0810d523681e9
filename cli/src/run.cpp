// The subcommands' flows: one call and print; watch (subscribe, then print
// events); speed (keep the motion alive while gportctl runs).
#include "gport/cli/run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <memory>

#include "geotag_dir.hpp"
#include "gport/cli/captures.hpp"
#include "gport/cli/monitor.hpp"
#include "gport/cli/output.hpp"
#include "gport/cli/printable.hpp"
#include "gport/cli/progress.hpp"
#include "gport/client/attitude_feed.hpp"
#include "gport/client/connection.hpp"
#include "gport/client/error.hpp"
#include "gport/contract/errors.hpp"
#include "gport/contract/names.hpp"
#include "wait.hpp"

namespace gport::cli {
namespace {

using client::Connection;
using nlohmann::json;
using namespace std::chrono_literals;

// Without --for, speed is re-sent this often for this long: if gportctl
// dies or hangs, the gimbal stops within the duration.
constexpr auto kResendEvery = 200ms;
constexpr auto kResendDuration = 500ms;
// speed --for shows its progress this often (attitude samples asked for).
constexpr double kProgressHz = 2.0;
// captures: the most gportd lists in one reply.
constexpr long kCapturesPage = 1000;

class Runner {
  public:
    Runner(const Invocation& inv, Connection& conn, std::ostream& out, std::ostream& err,
           Terminals terminals)
        : inv_(inv), conn_(conn), out_(out), err_(err), terminals_(terminals) {}

    int dispatch() {
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
        if (inv_.command == "geotag") {
            return geotag_dir(
                inv_, [this](auto& m, auto& p, auto& r) { return call(m, p, r); }, out_, err_);
        }
        if (inv_.command == "wait") {
            return wait_link(
                inv_, conn_, [this](auto& m, auto& p, auto& r) { return call(m, p, r); }, out_,
                err_);
        }
        json result;
        const int status = call(inv_.method, inv_.params, result);
        if (status != kExitOk) {
            return status;
        }
        print(result);
        if (inv_.command == "status" && !link_up(result.value("link", json()))) {
            return kExitLinkNotUp;  // a health check: printed as ever, but not 0
        }
        return inv_.wait && !reached(result) ? kExitNotReached : kExitOk;
    }

  private:
    // gportctl call: the result as one line of JSON, or with --raw the whole
    // response (an error's too, besides the message on stderr).
    int call_any() {
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
    int call(const std::string& method, const json& params, json& result,
             json* response = nullptr) {
        std::optional<json> reply;
        try {
            reply = conn_.call(method, params, [this](const json& n) { notification(n); });
        } catch (const client::Error& e) {  // kTimeout: no reply within the call timeout
            err_ << "gportctl: " << printable(e.message()) << "\n";
            return kExitUnavailable;
        }
        if (!reply) {
            if (conn_.interrupted()) {
                return kExitInterrupted;
            }
            err_ << "gportctl: " << lost() << "\n";
            return kExitUnavailable;
        }
        if (response != nullptr) {
            *response = *reply;
        }
        if (reply->contains("error")) {
            const auto& error = (*reply)["error"];
            if (auto usage = option_refusal(error, params)) {
                err_ << "gportctl: " << *usage << "\nTry 'gportctl " << inv_.command
                     << " --help'.\n";
                return kExitUsage;
            }
            // `call` speaks the API, the other commands the command line.
            err_ << "gportctl: "
                 << format_error(inv_.command == "call" ? error : cli_wording(error)) << "\n";
            return kExitError;
        }
        result = reply->value("result", json());
        return kExitOk;
    }

    // Why the connection is gone: the library's reason (a line over its
    // limits, a request gportd did not read), else gportd closed it.
    std::string lost() const {
        return conn_.failure().empty() ? "the daemon closed the connection"
                                       : printable(conn_.failure());
    }

    // gportd's keepalive.max_duration_ms is known only to the daemon: its
    // refusal of a duration or lease is a usage error naming the option typed.
    // gportd says "duration_ms must be an integer from 1 to 60000
    // (keepalive.max_duration_ms)"; before 0.1.x's issue 22 its core said
    // "duration_ms = 120000 is out of range; allowed 1 to 60000".
    static std::optional<std::string> option_refusal(const json& error, const json& params) {
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
            } else if (const auto allowed = message.find("; allowed ");
                       allowed != std::string::npos) {
                range = message.substr(allowed + 10);
            } else {
                continue;
            }
            return fmt::format(
                "{}: {} ms is longer than gportd allows: {} ms (its keepalive.max_duration_ms)",
                option, params[param].dump(), printable(range));
        }
        return std::nullopt;
    }

    void print(const json& result) {
        out_ << (inv_.json ? json_line(result) + "\n" : format_result(inv_.command, result));
        out_.flush();
    }

    void notification(const json& message) {
        if (inv_.command == "captures") {
            if (message.value("method", "") == "capture") {
                followed_.push_back(message.value("params", json()));
            }
            return;
        }
        if (inv_.command != "watch") {
            return;
        }
        if (inv_.json) {
            out_ << json_line(message) << "\n";
        } else {
            if (inv_.timestamps) {
                out_ << format_timestamp(std::chrono::system_clock::now()) << " ";
            }
            out_ << format_notification(message);
        }
        out_.flush();
    }

    void print_capture(const json& capture) {
        out_ << (inv_.json  ? json_line(capture) + "\n"
                 : inv_.csv ? capture_csv_row(capture)
                            : capture_table_row(capture));
        out_.flush();
    }

    // Pages through the captures from `since` with each reply's `next`
    // until gportd says there are no more (a page may hold fewer than asked
    // for: gportd bounds it in bytes too), or --limit were printed.
    int list_captures(std::uint64_t& since) {
        long left = inv_.limit.value_or(std::numeric_limits<long>::max());
        for (bool more = true; more && left > 0;) {
            json result;
            const json params = {{"since", since}, {"limit", std::min(left, kCapturesPage)}};
            if (const int s = call(contract::method::kCaptures, params, result); s != kExitOk) {
                return s;
            }
            const auto page = read_captures_page(result, since);
            for (auto it = page.captures.begin(); it != page.captures.end() && left > 0; ++it) {
                print_capture(*it);
                --left;
            }
            since = page.next;
            more = page.more;
        }
        return kExitOk;
    }

    // The listing; with --follow, subscribed first so nothing falls between
    // the list and the tail, then each capture notification not listed yet.
    int captures() {
        json ignored;
        if (inv_.follow) {
            if (const int s =
                    call(contract::method::kSubscribe, {{"topics", {"capture"}}}, ignored);
                s != kExitOk) {
                return s;
            }
        }
        if (!inv_.json) {
            out_ << (inv_.csv ? captures_csv_header() : captures_table_header());
        }
        std::uint64_t since = inv_.since;
        const int listed = list_captures(since);
        if (inv_.follow && listed == kExitInterrupted) {
            return kExitOk;  // Ctrl-C ends a follow, also while it still lists
        }
        if (listed != kExitOk || !inv_.follow) {
            return listed;
        }
        for (;;) {
            for (const auto& capture : followed_) {
                if (const auto index = capture_index(capture); index && *index >= since) {
                    print_capture(capture);
                    since = *index + 1;
                }
            }
            followed_.clear();
            json message;
            const auto status = conn_.read(message);
            if (status == Connection::ReadStatus::kMessage) {
                notification(message);
            } else if (status == Connection::ReadStatus::kInterrupted) {
                return kExitOk;
            } else if (status == Connection::ReadStatus::kClosed) {
                err_ << "gportctl: " << lost() << "\n";
                return kExitUnavailable;
            }
        }
    }

    // Until Ctrl-C, or -n COUNT events, or --for DURATION (exit 0 for all three).
    // With --shared-memory, attitude comes from the library's feed, whose
    // descriptor the connection polls with the socket.
    int watch() {
        json params = inv_.params;
        std::unique_ptr<client::AttitudeFeed> feed;
        if (inv_.shared_memory) {
            auto& topics = params["topics"];
            const auto before = topics.size();
            topics.erase(std::remove(topics.begin(), topics.end(), "attitude"), topics.end());
            if (topics.size() != before) {
                if (auto status = open_feed(feed); status != kExitOk) {
                    return status;
                }
            }
        }
        const Unwatch unwatch{conn_};  // before the feed goes
        json result = {{"topics", json::array()}};
        if (!params["topics"].empty()) {
            if (const int status = call(contract::method::kSubscribe, params, result);
                status != kExitOk) {
                return status;
            }
        }
        if (feed) {
            result["topics"] = inv_.topics;  // as gportd would list them
            conn_.watch(feed->fd());
        }
        // What is watched, for the person at the terminal; never in the
        // output a script reads.
        if (terminals_.err) {
            err_ << format_result("watch", result);
            err_.flush();
        }
        const bool timed = inv_.duration.has_value();
        const auto deadline = timed ? std::chrono::steady_clock::now() + *inv_.duration
                                    : std::chrono::steady_clock::time_point::max();
        long seen = 0;
        json message;
        while (!inv_.count || seen < *inv_.count) {
            const auto status = timed ? conn_.read(message, until(deadline)) : conn_.read(message);
            if (status == Connection::ReadStatus::kWoken) {
                print_samples(*feed, seen);
            } else if (auto done = handle_read(status, message, seen)) {
                return *done;
            }
            if (timed && std::chrono::steady_clock::now() >= deadline) {
                return kExitOk;
            }
        }
        return kExitOk;
    }

    // watch: the feed's new samples, as gportd's notifications (up to -n).
    void print_samples(client::AttitudeFeed& feed, long& seen) {
        feed.reset();
        while (!inv_.count || seen < *inv_.count) {
            const auto sample = feed.take();
            if (!sample) {
                return;
            }
            notification(client::attitude_notification(*sample));
            ++seen;
        }
    }

    struct Unwatch {
        Connection& conn;
        ~Unwatch() { conn.watch(-1); }
    };

    // watch: a read's outcome other than a wake; the exit status when it
    // ends the watch.
    std::optional<int> handle_read(Connection::ReadStatus status, const json& message, long& seen) {
        switch (status) {
            case Connection::ReadStatus::kMessage:
                if (!message.contains("id")) {
                    notification(message);
                    ++seen;
                }
                return std::nullopt;
            case Connection::ReadStatus::kInterrupted:
                return kExitOk;
            case Connection::ReadStatus::kClosed:
                err_ << "gportctl: " << lost() << "\n";
                return kExitUnavailable;
            default:
                return std::nullopt;
        }
    }

    int open_feed(std::unique_ptr<client::AttitudeFeed>& feed) {
        try {
            feed = std::make_unique<client::AttitudeFeed>(
                conn_.attitude_channel([this](const json& n) { notification(n); }));
        } catch (const client::Error& e) {
            if (e.transport() && conn_.interrupted()) {
                return kExitInterrupted;
            }
            if (e.transport() && conn_.closed()) {
                err_ << "gportctl: the daemon closed the connection\n";
                return kExitUnavailable;
            }
            err_ << "gportctl: " << format_error(e) << "\n";
            return e.transport() ? kExitUnavailable : kExitError;
        }
        return kExitOk;
    }

    static std::chrono::milliseconds until(std::chrono::steady_clock::time_point when) {
        return std::max(std::chrono::milliseconds(0),
                        std::chrono::duration_cast<std::chrono::milliseconds>(
                            when - std::chrono::steady_clock::now()));
    }

    // Sends stop on the way out, ignoring the interruption that asked for it.
    int stop_and_exit() {
        conn_.interrupted = [] { return false; };
        json ignored;
        const int status = call(contract::method::kStop, json::object(), ignored);
        if (status == kExitOk && !inv_.json) {
            out_ << "stopped\n";
        }
        return status;
    }

    // The daemon keeps the motion alive; we stay connected until it ends
    // (it would stop the motion of a client that disconnects), showing its
    // progress from attitude samples a few times a second, then how it ended.
    int speed_for() {
        json result;
        if (const int status =
                call(contract::method::kSubscribe,
                     {{"topics", {"motion", "attitude"}}, {"max_rate_hz", kProgressHz}}, result);
            status != kExitOk) {
            return status;
        }
        if (const int status = call(contract::method::kSpeed, inv_.params, result);
            status != kExitOk) {
            return status;
        }
        print(result);
        Progress progress(out_, *inv_.duration, terminals_.out && !inv_.json);
        const auto deadline = std::chrono::steady_clock::now() + *inv_.duration + 2s;
        json message;
        while (std::chrono::steady_clock::now() < deadline) {
            switch (conn_.read(message, until(deadline))) {
                case Connection::ReadStatus::kMessage:
                    if (message.value("method", "") == "attitude" && !inv_.json) {
                        progress.show(message["params"]);
                    } else if (motion_over(message)) {
                        progress.end(message["params"], inv_.json);
                        return kExitOk;
                    }
                    break;
                case Connection::ReadStatus::kInterrupted:
                    progress.end(json::object(), true);
                    return stop_and_exit();
                case Connection::ReadStatus::kClosed:
                    progress.end(json::object(), true);
                    err_ << "gportctl: " << lost() << "\n";
                    return kExitUnavailable;
                case Connection::ReadStatus::kTimeout:
                    return kExitOk;
                case Connection::ReadStatus::kWoken:
                    break;  // nothing watched here
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
        if (const int status = call(contract::method::kSpeed, params, result); status != kExitOk) {
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
            if (const int status = call(contract::method::kSpeed, params, result);
                status != kExitOk) {
                return conn_.interrupted() ? stop_and_exit() : status;
            }
        }
    }

    const Invocation& inv_;
    Connection& conn_;
    std::ostream& out_;
    std::ostream& err_;
    Terminals terminals_;
    std::vector<json> followed_;  // captures --follow: notifications not yet printed
};

}  // namespace

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
    std::optional<Connection> opened;
    try {
        opened.emplace(Connection::open(invocation.socket));
    } catch (const client::Error& e) {
        err << "gportctl: " << printable(e.what()) << "\n";
        return kExitUnavailable;
    }
    auto& conn = *opened;
    conn.interrupted = std::move(interrupted);
    return Runner(invocation, conn, out, err, terminals).dispatch();
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
