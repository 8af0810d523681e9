#include "settings_exchange.hpp"

#include <fmt/format.h>

namespace gport::daemon {

namespace gp = gport::protocol;

SettingsExchange::SettingsExchange(boost::asio::io_context& io, const config::RequestConfig& config,
                                   Send send)
    : timer_(io), config_(config), send_(std::move(send)) {}

void SettingsExchange::get(Done done) {
    jobs_.push_back(Job{std::nullopt, std::move(done), Step::kRead, 0, {}});
    begin_next();
}

void SettingsExchange::set(SettingsChange change, Done done) {
    jobs_.push_back(Job{change, std::move(done), Step::kRead, 0, {}});
    begin_next();
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
    if (!send_(frame)) {
        finish(CommandError{ErrorCode::kLinkDown, "gimbal link down: serial device not open"});
        return;
    }
    timer_.expires_after(config_.timeout);
    timer_.async_wait([this](boost::system::error_code ec) {
        if (!ec) {
            on_timeout();
        }
    });
}

void SettingsExchange::on_timeout() {
    Job& job = jobs_.front();
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
    job.done(std::move(result));
    begin_next();
}

void SettingsExchange::abort_all(const CommandError& error) {
    timer_.cancel();
    auto jobs = std::exchange(jobs_, {});
    running_ = false;
    for (auto& job : jobs) {
        job.done(error);
    }
}

}  // namespace gport::daemon
