#include "wait.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <optional>
#include <utility>

#include "gport/cli/printable.hpp"
#include "gport/contract/names.hpp"

namespace gport::cli {
namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

std::string describe(const json& link) {
    const auto state = link.is_object() ? link.value("state", json()) : json();
    const auto reason = link.is_object() ? link.value("reason", json()) : json();
    std::string text = printable(state.is_string() ? state.get<std::string>() : "unknown");
    if (reason.is_string() && !reason.get<std::string>().empty()) {
        text += " (" + printable(reason.get<std::string>()) + ")";
    }
    return text;
}

class LinkWait {
  public:
    LinkWait(const Invocation& inv, client::Client& gportd, std::ostream& out, std::ostream& err)
        : inv_(inv), gportd_(gportd), out_(out), err_(err) {
        if (inv.timeout) {
            deadline_ = Clock::now() + *inv.timeout;
        }
        // Every link notification, from the subscription on (also those
        // that come with the status reply: they are older than it).
        gportd_.on_notification_json([this](const std::string& text) {
            const auto message = json::parse(text, nullptr, false);
            // The first "up" of a batch is kept: a link that came up and
            // went again between two looks still ends the wait, as it
            // would have read one by one.
            if (message.is_object() && message.value("method", "") == contract::kTopicLink &&
                !(pending_ && link_up(*pending_))) {
                pending_ = message.value("params", json::object());
            }
        });
    }

    // After the subscription and status: reads link notifications until
    // one says up, or the deadline.
    int until_up(const json& status_link) {
        link_ = status_link;
        pending_.reset();
        while (!link_up(link_)) {
            try {
                gportd_.dispatch(deadline_ ? std::min(left(), kSlice) : kSlice);
            } catch (const client::Error& e) {
                err_ << "gportctl: wait link: " << printable(e.message()) << "\n";
                return kExitUnavailable;
            }
            if (pending_) {
                link_ = *std::exchange(pending_, std::nullopt);
            }
            if (interrupted_()) {
                return kExitInterrupted;
            }
            if (deadline_ && Clock::now() >= *deadline_ && !link_up(link_)) {
                return timed_out();
            }
        }
        out_ << (inv_.json ? json_line(link_) + "\n" : "link: " + describe(link_) + "\n");
        out_.flush();
        return kExitOk;
    }

    void on_interrupt(std::function<bool()> interrupted) { interrupted_ = std::move(interrupted); }

  private:
    static constexpr std::chrono::milliseconds kSlice{100};

    std::chrono::milliseconds left() const {
        return std::max(
            std::chrono::milliseconds(0),
            std::chrono::duration_cast<std::chrono::milliseconds>(*deadline_ - Clock::now()));
    }

    int timed_out() {
        const auto ms = inv_.timeout->count();
        err_ << fmt::format(
            "gportctl: wait link: the link is not up after {} (link: {})\n",
            ms % 1000 == 0 ? fmt::format("{} s", ms / 1000) : fmt::format("{} ms", ms),
            describe(link_));
        return kExitLinkNotUp;
    }

    const Invocation& inv_;
    client::Client& gportd_;
    std::ostream& out_;
    std::ostream& err_;
    std::optional<Clock::time_point> deadline_;
    json link_;
    std::optional<json> pending_;  // the newest link notification not yet looked at
    std::function<bool()> interrupted_ = [] { return false; };
};

}  // namespace

bool link_up(const json& link) {
    return link.is_object() && link.value("state", json()) == "up";
}

int wait_link(const Invocation& inv, client::Client& gportd, const CallFn& call,
              const std::function<bool()>& interrupted, std::ostream& out, std::ostream& err) {
    LinkWait wait(inv, gportd, out, err);  // the timeout counts from here
    wait.on_interrupt(interrupted);
    json result;
    if (const int s = call(contract::method::kSubscribe,
                           {{"topics", {std::string(contract::kTopicLink)}}}, result);
        s != kExitOk) {
        return s;
    }
    // Notifications that came before status's reply are older than it.
    if (const int s = call(contract::method::kStatus, json::object(), result); s != kExitOk) {
        return s;
    }
    return wait.until_up(result.value("link", json::object()));
}

}  // namespace gport::cli
