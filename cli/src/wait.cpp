#include "wait.hpp"

#include <fmt/format.h>

#include <chrono>
#include <optional>

#include "gport/cli/printable.hpp"
#include "gport/contract/names.hpp"

namespace gport::cli {
namespace {

using client::Connection;
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
    LinkWait(const Invocation& inv, Connection& conn, std::ostream& out, std::ostream& err)
        : inv_(inv), conn_(conn), out_(out), err_(err) {
        if (inv.timeout) {
            deadline_ = Clock::now() + *inv.timeout;
        }
    }

    // After the subscription and status: reads link notifications until
    // one says up, or the deadline.
    int until_up(const json& status_link) {
        link_ = status_link;
        json message;
        while (!link_up(link_)) {
            const auto status = deadline_ ? conn_.read(message, left()) : conn_.read(message);
            if (status == Connection::ReadStatus::kMessage) {
                if (message.value("method", "") == "link") {
                    link_ = message.value("params", json::object());
                }
            } else if (status == Connection::ReadStatus::kTimeout) {
                return timed_out();
            } else if (status == Connection::ReadStatus::kInterrupted) {
                return kExitInterrupted;
            } else if (status == Connection::ReadStatus::kClosed) {
                err_ << "gportctl: wait link: "
                     << (conn_.failure().empty() ? "the daemon closed the connection"
                                                 : printable(conn_.failure()))
                     << "\n";
                return kExitUnavailable;
            }
            if (deadline_ && Clock::now() >= *deadline_ && !link_up(link_)) {
                return timed_out();
            }
        }
        out_ << (inv_.json ? json_line(link_) + "\n" : "link: " + describe(link_) + "\n");
        out_.flush();
        return kExitOk;
    }

  private:
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
    Connection& conn_;
    std::ostream& out_;
    std::ostream& err_;
    std::optional<Clock::time_point> deadline_;
    json link_;
};

}  // namespace

bool link_up(const json& link) {
    return link.is_object() && link.value("state", json()) == "up";
}

int wait_link(const Invocation& inv, Connection& conn, const CallFn& call, std::ostream& out,
              std::ostream& err) {
    LinkWait wait(inv, conn, out, err);  // the timeout counts from here
    json result;
    if (const int s = call(contract::method::kSubscribe, {{"topics", {"link"}}}, result);
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
