#include "command_lane.hpp"

#include <boost/asio/post.hpp>

#include "gport/contract/names.hpp"
#include "gport/web/limits.hpp"

namespace gport::web {

namespace method = contract::method;

void refuse_busy(boost::asio::io_context& io, Reply reply, const std::string& why) {
    boost::asio::post(io, [reply = std::move(reply), why] {
        reply(client::Error(client::ErrorCode::kTooManyRequests,
                            "gport-web is busy: " + why + "; try again"),
              "");
    });
}

CommandLane::CommandLane(boost::asio::io_context& io, client::AsyncClient& client)
    : io_(io), client_(client), budget_(kCommandsPerSecond, kCommandBurst), refill_(io) {}

void CommandLane::stop(Reply reply) {
    jog_waiting_.reset();  // the stop is newer: the jog it replaces never goes
    stop_waiting_.push_back(std::move(reply));
    pump();
}

void CommandLane::jog(std::string params, Reply reply) {
    jog_waiting_ = Call{std::string(method::kSpeed), std::move(params), std::move(reply)};
    pump();
}

void CommandLane::call(std::string method, std::string params, Reply reply) {
    if (others_.size() >= kMaxCommandsWaiting) {
        refuse_busy(io_, std::move(reply),
                    std::to_string(kMaxCommandsWaiting) + " commands already wait for gportd");
        return;
    }
    others_.push_back(Call{std::move(method), std::move(params), std::move(reply)});
    pump();
}

void CommandLane::fail_all(const client::Error& error) {
    auto stops = std::exchange(stop_waiting_, {});
    auto jog = std::exchange(jog_waiting_, std::nullopt);
    auto others = std::exchange(others_, {});
    for (auto& reply : stops) {
        reply(error, "");
    }
    if (jog) {
        jog->reply(error, "");
    }
    for (auto& call : others) {
        call.reply(error, "");
    }
}

std::size_t CommandLane::waiting() const {
    return stop_waiting_.size() + (jog_waiting_ ? 1 : 0) + others_.size();
}

// Stops first, then the jog, then the others, each while the budget allows.
void CommandLane::pump() {
    if (!client_.connected()) {
        return;
    }
    send_stop();
    while (send_jog() || send_other()) {
    }
}

void CommandLane::send_stop() {
    if (stop_waiting_.empty()) {
        return;
    }
    if (!spend(0)) {
        wake_after_refill(0);
        return;
    }
    // Every stop that waited is answered by the one that goes.
    client_.async_call_json(method::kStop, "",
                            [replies = std::exchange(stop_waiting_, {})](
                                std::optional<client::Error> error, const std::string& result) {
                                for (const auto& reply : replies) {
                                    reply(error, result);
                                }
                            });
}

bool CommandLane::send_jog() {
    if (!jog_waiting_ || jog_in_flight_ || !stop_waiting_.empty()) {
        return false;
    }
    if (!spend(kStopReserve)) {
        wake_after_refill(kStopReserve);
        return false;
    }
    auto call = std::move(*jog_waiting_);
    jog_waiting_.reset();
    jog_in_flight_ = true;
    client_.async_call_json(call.method, call.params,
                            [this, reply = std::move(call.reply)](
                                std::optional<client::Error> error, const std::string& result) {
                                jog_in_flight_ = false;
                                reply(error, result);
                                pump();
                            });
    return true;
}

bool CommandLane::send_other() {
    if (others_.empty() || others_in_flight_ >= kMaxCommandsInFlight || !stop_waiting_.empty()) {
        return false;
    }
    if (!spend(kStopReserve)) {
        wake_after_refill(kStopReserve);
        return false;
    }
    auto call = std::move(others_.front());
    others_.pop_front();
    ++others_in_flight_;
    client_.async_call_json(call.method, call.params,
                            [this, reply = std::move(call.reply)](
                                std::optional<client::Error> error, const std::string& result) {
                                --others_in_flight_;
                                reply(error, result);
                                pump();
                            });
    return true;
}

bool CommandLane::spend(double keep) {
    const auto now = base::TokenBucket::Clock::now();
    return budget_.level(now) >= keep + 1 && budget_.take(now);
}

// One timer for the earliest wait: a stop's (keep 0) shortens a jog's.
void CommandLane::wake_after_refill(double keep) {
    const auto at = base::TokenBucket::Clock::now() +
                    budget_.wait_for(base::TokenBucket::Clock::now(), keep + 1);
    if (refill_armed_ && refill_.expiry() <= at) {
        return;
    }
    refill_armed_ = true;
    refill_.expires_at(at);  // cancels an earlier wait: its handler sees the new generation
    refill_.async_wait([this, generation = ++refill_generation_](boost::system::error_code ec) {
        if (ec || generation != refill_generation_) {
            return;
        }
        refill_armed_ = false;
        pump();
    });
}

}  // namespace gport::web
