// gportctl's commands that read notifications (runner.hpp): watch (until
// Ctrl-C, -n COUNT or --for), speed (keeps the motion alive while gportctl
// runs, or shows --for's progress), captures --follow.
#include <algorithm>
#include <limits>

#include "gport/cli/captures.hpp"
#include "gport/cli/output.hpp"
#include "gport/cli/printable.hpp"
#include "gport/client/capture_files.hpp"
#include "gport/contract/names.hpp"
#include "runner.hpp"

namespace gport::cli {

using nlohmann::json;
using namespace std::chrono_literals;

namespace {

// Without --for, speed is re-sent this often for this long: if gportctl
// dies or hangs, the gimbal stops within the duration.
constexpr auto kResendEvery = 200ms;
constexpr auto kResendDuration = 500ms;
// speed --for shows its progress this often (attitude samples asked for).
constexpr double kProgressHz = 2.0;
// captures: the most gportd lists in one reply.
constexpr long kCapturesPage = 1000;
// The longest a read waits before looking at the clock and -n again.
constexpr auto kSlice = 100ms;

std::chrono::milliseconds until(std::chrono::steady_clock::time_point when) {
    return std::max(0ms, std::chrono::duration_cast<std::chrono::milliseconds>(
                             when - std::chrono::steady_clock::now()));
}

bool motion_over(const json& message) {
    if (message.value("method", "") != contract::kTopicMotion) {
        return false;
    }
    const auto change = message["params"].value("change", "");
    return change == "ended" || change == "replaced";
}

}  // namespace

// Every notification, during calls and reads alike.
void Runner::notification(const json& message) {
    if (!message.is_object()) {
        return;
    }
    if (inv_.command == "captures") {
        if (message.value("method", "") == contract::kTopicCapture) {
            followed_.push_back(message.value("params", json()));
        }
    } else if (inv_.command == "watch") {
        watched(message);
    } else if (inv_.command == "speed") {
        speed_progress(message);
    }
}

// watch: printed as they come, up to -n.
void Runner::watched(const json& message) {
    if (inv_.count && seen_ >= *inv_.count) {
        return;
    }
    ++seen_;
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

// speed --for: attitude for the progress line, until the motion ends.
void Runner::speed_progress(const json& message) {
    if (progress_ == nullptr) {
        return;
    }
    if (message.value("method", "") == contract::kTopicAttitude && !inv_.json) {
        progress_->show(message["params"]);
    } else if (motion_over(message)) {
        progress_->end(message["params"], inv_.json);
        progress_ = nullptr;
        motion_over_ = true;
    }
}

// Reads notifications for `duration` (they go to notification()): 0, or
// 130 on Ctrl-C, or 69 when gportd goes away (said on stderr).
int Runner::pump(std::chrono::milliseconds duration) {
    try {
        gportd_.dispatch(duration);
    } catch (const client::Error& e) {
        return failed(e);
    }
    return interrupted_() ? kExitInterrupted : kExitOk;
}

// Until Ctrl-C, or -n COUNT events, or --for DURATION (exit 0 for all three).
int Runner::watch() {
    json result = {{"topics", json::array()}};
    std::vector<std::string> topics = inv_.topics;
    const bool attitude =
        std::find(topics.begin(), topics.end(), contract::kTopicAttitude) != topics.end();
    if (inv_.shared_memory && attitude) {
        if (const int s = watch_shared_memory(topics, result); s != kExitOk) {
            return s;
        }
    } else if (!inv_.params["topics"].empty()) {
        if (const int s = call(contract::method::kSubscribe, inv_.params, result); s != kExitOk) {
            return s;
        }
    }
    // What is watched, for the person at the terminal; never in the output
    // a script reads.
    if (terminals_.err) {
        try {
            err_ << format_result("watch", result);
        } catch (const client::Error& e) {
            return failed(e);
        }
        err_.flush();
    }
    const auto deadline = inv_.duration ? std::chrono::steady_clock::now() + *inv_.duration
                                        : std::chrono::steady_clock::time_point::max();
    while (!inv_.count || seen_ < *inv_.count) {
        const auto slice = inv_.duration
                               ? std::min<std::chrono::milliseconds>(kSlice, until(deadline))
                               : std::chrono::milliseconds(kSlice);
        if (const int s = pump(slice); s != kExitOk) {
            return s == kExitInterrupted ? kExitOk : s;
        }
        if (std::chrono::steady_clock::now() >= deadline) {
            return kExitOk;
        }
    }
    return kExitOk;
}

// watch --shared-memory with attitude: the Client subscribes the other
// topics on the socket and reads attitude from gportd's shared-memory
// channel; its samples reach notification() as gportd's notifications.
int Runner::watch_shared_memory(std::vector<std::string> topics, json& result) {
    client::SubscribeOptions options;
    options.shared_memory = true;
    if (inv_.params.contains("max_rate_hz")) {
        options.max_rate_hz = inv_.params["max_rate_hz"].get<double>();
    }
    try {
        gportd_.subscribe(topics, options);
    } catch (const client::Error& e) {
        return failed(e);
    }
    result["topics"] = std::move(topics);  // as gportd would list them
    return kExitOk;
}

// The daemon keeps the motion alive; we stay connected until it ends (it
// would stop the motion of a client that disconnects), showing its progress
// from attitude samples a few times a second, then how it ended.
int Runner::speed_for() {
    json result;
    if (const int s =
            call(contract::method::kSubscribe,
                 {{"topics",
                   {std::string(contract::kTopicMotion), std::string(contract::kTopicAttitude)}},
                  {"max_rate_hz", kProgressHz}},
                 result);
        s != kExitOk) {
        return s;
    }
    if (const int s = call(contract::method::kSpeed, inv_.params, result); s != kExitOk) {
        return s;
    }
    if (const int s = print(result); s != kExitOk) {
        return s;
    }
    // From here: a motion notification during the call may be about the
    // motion ours replaced, another client's.
    Progress progress(out_, *inv_.duration, terminals_.out && !inv_.json);
    progress_ = &progress;
    const auto deadline = std::chrono::steady_clock::now() + *inv_.duration + 2s;
    while (!motion_over_ && std::chrono::steady_clock::now() < deadline) {
        const int s = pump(std::min<std::chrono::milliseconds>(kSlice, until(deadline)));
        if (s != kExitOk) {
            progress.end(json::object(), true);
            progress_ = nullptr;
            return s == kExitInterrupted ? stop_and_exit() : s;
        }
    }
    progress_ = nullptr;
    return kExitOk;
}

int Runner::speed_until_interrupted() {
    json params = inv_.params;
    params["duration_ms"] = std::chrono::milliseconds(kResendDuration).count();
    json result;
    if (const int s = call(contract::method::kSpeed, params, result); s != kExitOk) {
        return s;
    }
    if (!inv_.json) {
        out_ << "moving; Ctrl-C to stop\n";
        out_.flush();
    }
    while (true) {
        if (const int s = pump(kResendEvery); s != kExitOk) {
            return s == kExitInterrupted ? stop_and_exit() : s;
        }
        if (const int s = call(contract::method::kSpeed, params, result); s != kExitOk) {
            return s == kExitInterrupted || interrupted_() ? stop_and_exit() : s;
        }
    }
}

void Runner::print_capture(const json& capture) {
    out_ << (inv_.json  ? json_line(capture) + "\n"
             : inv_.csv ? capture_csv_row(capture)
                        : capture_table_row(capture));
    out_.flush();
}

// Pages through the captures from `since` with each reply's `next` until
// gportd says there are no more (a page may hold fewer than asked for:
// gportd bounds it in bytes too), or --limit were printed.
int Runner::list_captures(std::uint64_t& since) {
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

// The listing; with --follow, subscribed first so nothing falls between the
// list and the tail, then each capture notification not listed yet.
int Runner::captures() {
    json ignored;
    if (inv_.follow) {
        if (const int s = call(contract::method::kSubscribe,
                               {{"topics", {std::string(contract::kTopicCapture)}}}, ignored);
            s != kExitOk) {
            return s;
        }
    }
    if (!inv_.json) {
        out_ << (inv_.csv ? client::captures_csv_header() : captures_table_header());
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
        if (const int s = pump(kSlice); s != kExitOk) {
            return s == kExitInterrupted ? kExitOk : s;
        }
    }
}

}  // namespace gport::cli
