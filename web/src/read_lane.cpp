#include "read_lane.hpp"

#include <boost/asio/post.hpp>

#include "gport/web/limits.hpp"

namespace gport::web {

ReadLane::ReadLane(boost::asio::io_context& io, client::AsyncClient& client)
    : io_(io), client_(client) {}

void ReadLane::snapshot(const std::string& method, Reply reply) {
    auto& snap = snapshots_[method];
    if (snap.result && Clock::now() - snap.at < kSnapshotMaxAge) {
        boost::asio::post(io_, [reply = std::move(reply), result = *snap.result] {
            reply(std::nullopt, result);
        });
        return;
    }
    if (snap.waiting.size() >= kMaxReadsWaiting) {
        refuse_busy(io_, std::move(reply), "too many requests wait for gportd's " + method);
        return;
    }
    snap.waiting.push_back(std::move(reply));
    if (!snap.fetching) {
        fetch(method);
    }
}

void ReadLane::fetch(const std::string& method) {
    snapshots_[method].fetching = true;
    client_.async_call_json(
        method, "", [this, method](std::optional<client::Error> error, const std::string& result) {
            auto& snap = snapshots_[method];
            snap.fetching = false;
            if (!error) {
                snap.result = result;
                snap.at = Clock::now();
            }
            for (const auto& reply : std::exchange(snap.waiting, {})) {
                reply(error, result);
            }
        });
}

void ReadLane::invalidate(const std::string& method) {
    snapshots_[method].result.reset();
}

void ReadLane::call(std::string method, std::string params, Reply reply) {
    if (waiting_.size() >= kMaxReadsWaiting) {
        refuse_busy(io_, std::move(reply),
                    std::to_string(kMaxReadsWaiting) + " reads already wait for gportd");
        return;
    }
    waiting_.push_back(Call{std::move(method), std::move(params), std::move(reply)});
    pump();
}

void ReadLane::pump() {
    while (!waiting_.empty() && in_flight_ < kMaxReadsInFlight && client_.connected()) {
        auto call = std::move(waiting_.front());
        waiting_.pop_front();
        ++in_flight_;
        client_.async_call_json(call.method, call.params,
                                [this, reply = std::move(call.reply)](
                                    std::optional<client::Error> error, const std::string& result) {
                                    --in_flight_;
                                    reply(error, result);
                                    pump();
                                });
    }
}

void ReadLane::fail_all(const client::Error& error) {
    for (auto& [method, snap] : snapshots_) {
        snap.result.reset();
    }
    for (auto& call : std::exchange(waiting_, {})) {
        call.reply(error, "");
    }
}

}  // namespace gport::web
