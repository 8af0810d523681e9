#include "gateway.hpp"

#include <spdlog/spdlog.h>

#include <boost/asio/post.hpp>
#include <nlohmann/json.hpp>

#include "gport/contract/names.hpp"
#include "gport/web/limits.hpp"

namespace gport::web {

using nlohmann::json;

Message gportd_message(bool connected, const std::string& reason) {
    const json message = {{"method", "gportd"},
                          {"params", {{"connected", connected}, {"reason", reason}}}};
    return std::make_shared<const std::string>(
        message.dump(-1, ' ', false, json::error_handler_t::replace));
}

Gateway::Gateway(boost::asio::io_context& io, std::string socket, Registry& registry)
    : io_(io),
      socket_(std::move(socket)),
      registry_(registry),
      client_(io),
      commands_(io),
      command_lane_(io, commands_),
      read_lane_(io, client_),
      reconnect_(io),
      status_(io) {
    state_ = gportd_message(false, "connecting to gportd");
    client_.on_notification_text([this](const std::string& topic, const std::string& line) {
        registry_.broadcast(std::make_shared<const std::string>(line),
                            topic == contract::kTopicAttitude);
    });
    client_.on_disconnect(
        [this](const client::Error& error) { lost("lost gportd", error.message()); });
    commands_.on_disconnect(
        [this](const client::Error& error) { lost("lost gportd", error.message()); });
}

void Gateway::start() {
    connect();
    poll_status();
}

void Gateway::connect() {
    client_.async_connect(socket_, [this](std::optional<client::Error> error) {
        if (error) {
            lost("cannot reach gportd", error->message());
            return;
        }
        connect_commands();
    });
}

void Gateway::connect_commands() {
    commands_.async_connect(socket_, [this](std::optional<client::Error> error) {
        if (error) {
            client_.close();
            lost("cannot reach gportd", error->message());
            return;
        }
        subscribe();
    });
}

void Gateway::subscribe() {
    const json params = {{"topics",
                          {contract::kTopicAttitude, contract::kTopicLink, contract::kTopicMotion,
                           contract::kTopicCapture}},
                         {"max_rate_hz", kAttitudeMaxRateHz}};
    client_.async_call_json(contract::method::kSubscribe, params.dump(),
                            [this](std::optional<client::Error> error, const std::string&) {
                                if (error) {
                                    client_.close();
                                    commands_.close();
                                    lost("gportd refused the subscription", error->message());
                                    return;
                                }
                                connected_ = true;
                                if (announced_down_) {
                                    spdlog::info("gportd reachable again on {}", socket_);
                                } else {
                                    spdlog::info("connected to gportd on {}", socket_);
                                }
                                announced_down_ = false;
                                registry_.broadcast(gportd_message(true, "connected"), false);
                            });
}

void Gateway::lost(const std::string& reason, const std::string& detail) {
    const bool was = connected_;
    connected_ = false;
    // Either connection broke: both start again together.
    client_.close();
    commands_.close();
    const client::Error gone(client::ErrorCode::kTransport, "gportd is not connected");
    command_lane_.fail_all(gone);
    read_lane_.fail_all(gone);
    state_ = gportd_message(false, reason);
    if (was || !announced_down_) {
        announced_down_ = true;
        spdlog::warn("gportd not reachable: {}: {} (retrying every second)", reason, detail);
        registry_.broadcast(state_, false);
    }
    retry();
}

void Gateway::close() {
    stopped_ = true;
    connected_ = false;
    reconnect_.cancel();
    status_.cancel();
    client_.close();
    commands_.close();
}

void Gateway::retry() {
    if (stopped_) {
        return;
    }
    reconnect_.expires_after(kReconnectPeriod);
    reconnect_.async_wait([this](boost::system::error_code ec) {
        if (!ec) {
            connect();
        }
    });
}

void Gateway::poll_status() {
    status_.expires_after(kStatusPeriod);
    status_.async_wait([this](boost::system::error_code ec) {
        if (ec || stopped_) {
            return;
        }
        if (connected_ && registry_.listening() > 0) {
            read_lane_.snapshot(
                contract::method::kStatus,
                [this](std::optional<client::Error> error, const std::string& result) {
                    if (!error) {
                        registry_.broadcast(std::make_shared<const std::string>(
                                                R"({"method":"status","params":)" + result + "}"),
                                            false);
                    }
                });
        }
        poll_status();
    });
}

bool Gateway::refused_offline(Reply& reply) {
    if (connected_) {
        return false;
    }
    boost::asio::post(io_, [reply = std::move(reply)] {
        reply(client::Error(client::ErrorCode::kTransport, "gportd is not connected"), "");
    });
    return true;
}

void Gateway::stop(Reply reply) {
    if (!refused_offline(reply)) {
        command_lane_.stop(std::move(reply));
    }
}

void Gateway::jog(std::string params, Reply reply) {
    if (!refused_offline(reply)) {
        command_lane_.jog(std::move(params), std::move(reply));
    }
}

void Gateway::command(const std::string& method, std::string params, Reply reply) {
    if (refused_offline(reply)) {
        return;
    }
    if (method == contract::method::kSetSettings) {
        // The settings changed (or may have): the next read fetches them.
        reply = [this, reply = std::move(reply)](std::optional<client::Error> error,
                                                 const std::string& result) {
            read_lane_.invalidate(contract::method::kGetSettings);
            reply(error, result);
        };
    }
    command_lane_.call(method, std::move(params), std::move(reply));
}

void Gateway::snapshot(const std::string& method, Reply reply) {
    if (!refused_offline(reply)) {
        read_lane_.snapshot(method, std::move(reply));
    }
}

void Gateway::read(const std::string& method, std::string params, Reply reply) {
    if (!refused_offline(reply)) {
        read_lane_.call(method, std::move(params), std::move(reply));
    }
}

}  // namespace gport::web
