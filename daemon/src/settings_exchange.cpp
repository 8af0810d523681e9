#include "gport/daemon/core/settings_exchange.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <boost/asio/post.hpp>

namespace gport::daemon {

namespace gp = gport::protocol;

namespace {

// "dead_zone 10 -> 5, inverted no -> yes": the values a set changed, or that
// nothing did.
std::string describe_change(const gp::SettingsBlock& before, const gp::SettingsBlock& after) {
    std::string out;
    const auto add = [&](const char* name, const std::string& from, const std::string& to) {
        if (from != to) {
            out += fmt::format("{}{} {} -> {}", out.empty() ? "" : ", ", name, from, to);
        }
    };
    add("dead_zone", std::to_string(before.dead_zone), std::to_string(after.dead_zone));
    add("follow_speed", std::to_string(before.follow_speed), std::to_string(after.follow_speed));
    add("inverted", before.inverted() ? "yes" : "no", after.inverted() ? "yes" : "no");
    return out.empty() ? "nothing changed (the values asked for were already set)" : out;
}

}  // namespace

SettingsExchange::SettingsExchange(boost::asio::io_context& io, const config::RequestConfig& config,
                                   Send send, std::shared_ptr<spdlog::logger> log)
    : timer_(io), config_(config), send_(std::move(send)), log_(std::move(log)) {}

std::optional<CommandError> SettingsExchange::admit(std::uint64_t client) const {
    const auto mine =
        std::ranges::count_if(jobs_, [&](const Job& j) { return j.client == client; });
    if (static_cast<std::size_t>(mine) >= kMaxPerClient) {
        return CommandError{ErrorCode::kTooManyRequests,
                            fmt::format("too many settings requests: at most {} per client may "
                                        "wait for the gimbal; wait for a reply, then retry",
                                        kMaxPerClient)};
    }
    if (jobs_.size() >= kMaxTotal) {
        return CommandError{ErrorCode::kTooManyRequests,
                            fmt::format("too many settings requests: at most {} from all clients "
                                        "may wait for the gimbal; retry later",
                                        kMaxTotal)};
    }
    return std::nullopt;
}

void SettingsExchange::request(std::uint64_t client, std::optional<CommandError> refused,
                               std::optional<SettingsChange> change, Api::SettingsCallback done) {
    if (!refused) {
        refused = admit(client);
    }
    if (refused) {
        boost::asio::post(timer_.get_executor(),
                          [done = std::move(done), e = std::move(*refused)] { done(e); });
        return;
    }
    Reply reply = [done = std::move(done)](Outcome<gp::SettingsBlock> r) {
        if (!r) {
            done(r.error());
            return;
        }
        done(Settings{r->dead_zone, r->follow_speed, r->inverted()});
    };
    enqueue(Job{client, change, std::move(reply), Step::kRead, 0, {}, std::nullopt, std::nullopt});
}

void SettingsExchange::get(std::uint64_t client, Reply reply) {
    enqueue(Job{
        client, std::nullopt, std::move(reply), Step::kRead, 0, {}, std::nullopt, std::nullopt});
}

void SettingsExchange::set(std::uint64_t client, SettingsChange change, Reply reply) {
    enqueue(Job{client, change, std::move(reply), Step::kRead, 0, {}, std::nullopt, std::nullopt});
}

void SettingsExchange::enqueue(Job job) {
    jobs_.push_back(std::move(job));
    begin_next();
}

void SettingsExchange::forget(std::uint64_t client) {
    for (auto& job : jobs_) {
        if (job.client == client) {
            job.reply = nullptr;
        }
    }
    // The running one stays: its exchange with the gimbal completes.
    const auto first_waiting = jobs_.begin() + (running_ ? 1 : 0);
    jobs_.erase(std::remove_if(first_waiting, jobs_.end(),
                               [&](const Job& j) { return j.client == client; }),
                jobs_.end());
}

void SettingsExchange::begin_next() {
    if (running_ || jobs_.empty()) {
        return;
    }
    running_ = true;
    send_step();
}

void SettingsExchange::send_step() {
    Job& job = jobs_.front();
    const gp::Frame frame = job.step == Step::kWrite ? gp::encode(gp::SetSettings{job.block})
                                                     : gp::encode(gp::GetSettings{});
    // A refused frame fails the request from the timer, never from inside
    // get()/set(): the caller must not be called back from its own call.
    job.refused = send_(frame);
    timer_.expires_after(job.refused ? config::Millis{0} : config_.timeout);
    timer_.async_wait([this](boost::system::error_code ec) {
        if (!ec) {
            on_timeout();
        }
    });
}

void SettingsExchange::on_timeout() {
    Job& job = jobs_.front();
    if (job.refused) {
        finish(*job.refused);
        return;
    }
    ++timeouts_;
    if (job.attempt < config_.retries) {
        ++job.attempt;
        send_step();
        return;
    }
    const char* what = job.step == Step::kWrite ? "0x15 (set settings) with 0x16"
                                                : "0x13 (read settings) with 0x14";
    finish(CommandError{ErrorCode::kNoAnswer,
                        fmt::format("gimbal did not answer {} after {} attempt(s) of {} ms", what,
                                    job.attempt + 1, config_.timeout.count())});
}

void SettingsExchange::on_report(const gp::SettingsBlock& block) {
    if (running_ && jobs_.front().step != Step::kWrite) {
        advance(&block);
    }
}

void SettingsExchange::on_ack() {
    if (running_ && jobs_.front().step == Step::kWrite) {
        advance(nullptr);
    }
}

void SettingsExchange::advance(const gp::SettingsBlock* report) {
    timer_.cancel();
    Job& job = jobs_.front();
    job.attempt = 0;
    if (report != nullptr) {
        job.block = *report;
    }
    if (job.step == Step::kRead && job.change) {
        const auto& c = *job.change;
        job.before = job.block;
        job.block.dead_zone = c.dead_zone.value_or(job.block.dead_zone);
        job.block.follow_speed = c.follow_speed.value_or(job.block.follow_speed);
        if (c.inverted) {
            job.block.set_inverted(*c.inverted);
        }
        job.step = Step::kWrite;
    } else if (job.step == Step::kWrite) {
        job.step = Step::kReadBack;
    } else {
        finish(job.block);
        return;
    }
    send_step();
}

void SettingsExchange::finish(Outcome<gp::SettingsBlock> result) {
    timer_.cancel();
    Job job = std::move(jobs_.front());
    jobs_.pop_front();
    running_ = false;
    if (result && job.before) {
        log_->info("settings changed by client {}: {}", job.client,
                   describe_change(*job.before, *result));
    }
    if (job.reply) {
        job.reply(std::move(result));
    }
    begin_next();
}

void SettingsExchange::abort_all(const CommandError& error) {
    timer_.cancel();
    auto jobs = std::exchange(jobs_, {});
    running_ = false;
    for (auto& job : jobs) {
        if (job.reply) {
            job.reply(error);
        }
    }
}

}  // namespace gport::daemon
