// The asynchronous client: one socket on the caller's io_context, a queue of
// whole request lines with one write in flight, one read loop that matches
// replies to pending calls by id and hands notifications on, and a timer per
// call (the call timeout). The JSON codec is the blocking client's
// (codec.hpp), the line limits the blocking transport's (lines.hpp).
#include "gport/client/async_client.hpp"

#include <unistd.h>

#include <algorithm>
#include <boost/asio/local/stream_protocol.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/write.hpp>
#include <cerrno>
#include <cstring>
#include <deque>
#include <iterator>
#include <map>
#include <utility>

#include "attitude_feed.hpp"
#include "channel_claims.hpp"
#include "codec.hpp"
#include "connect_error.hpp"
#include "gport/base/descriptors.hpp"
#include "gport/contract/names.hpp"
#include "lines.hpp"

namespace gport::client {

namespace asio = boost::asio;
using nlohmann::json;
using Socket = asio::local::stream_protocol::socket;
using RawHandler = std::function<void(std::optional<Error>, const json&)>;

struct AsyncClient::Impl : std::enable_shared_from_this<Impl> {
    explicit Impl(asio::io_context& context) : io(context), socket(context) {}

    void connect(const std::string& path, std::function<void(std::optional<Error>)> handler) {
        shut("the connection was replaced by a new connect");
        socket = Socket(io);
        const auto generation = ++current;
        socket.async_connect(
            asio::local::stream_protocol::endpoint(path),
            [self = shared_from_this(), generation, path,
             handler = std::move(handler)](boost::system::error_code ec) {
                if (ec || generation != self->current) {
                    const auto why = ec ? ec.message() : std::string("cancelled");
                    handler(Error(ErrorCode::kTransport,
                                  detail::connect_failure(path, ec ? ec.value() : 0, why)));
                    return;
                }
                self->open = true;
                self->read(generation);
                handler(std::nullopt);
            });
    }

    void call(const std::string& method, const json& params, RawHandler handler) {
        if (!open) {
            asio::post(io, [handler = std::move(handler)] {
                handler(Error(ErrorCode::kTransport, "not connected to gportd (connect first)"),
                        json());
            });
            return;
        }
        const int id = next_id++;
        json request = {{"jsonrpc", "2.0"}, {"id", id}, {"method", method}};
        if (!params.empty()) {
            request["params"] = params;
        }
        if (method == contract::method::kAttitudeChannel) {
            claims.expect(id);  // two descriptors may come with its reply
        }
        auto& call = pending[id];
        call.handler = std::move(handler);
        if (const auto limit = codec::reply_limit(params, call_timeout)) {
            call.timer = std::make_unique<asio::steady_timer>(io, *limit);
            call.timer->async_wait([weak = weak_from_this(), id, method, limit,
                                    generation = current](boost::system::error_code ec) {
                const auto self = weak.lock();
                if (self && !ec && generation == self->current) {
                    self->expire(id, method, *limit);
                }
            });
        }
        outbox.emplace_back(id, request.dump() + "\n");
        if (outbox.size() == 1) {
            write(current);
        }
    }

    // The call's timer ran out: kTimeout, or, when gportd has not even
    // taken the request, the end of the connection.
    void expire(int id, const std::string& method, std::chrono::milliseconds limit) {
        const auto it = pending.find(id);
        if (it == pending.end()) {
            return;
        }
        const bool unsent = std::any_of(outbox.begin(), outbox.end(),
                                        [id](const auto& line) { return line.first == id; });
        if (unsent) {
            lost("gportd did not read the request to " + method + " within " +
                 std::to_string(limit.count()) +
                 " ms (the client's call timeout); the connection is closed");
            return;
        }
        auto call = std::move(it->second);  // the timer lives until its handler returns
        pending.erase(it);
        claims.abandon(id);  // a late reply's descriptors are closed
        call.handler(codec::no_reply(method, limit), json());
    }

    void write(std::uint64_t generation) {
        asio::async_write(
            socket, asio::buffer(outbox.front().second),
            [self = shared_from_this(), generation](boost::system::error_code ec, std::size_t) {
                if (generation != self->current) {
                    return;
                }
                if (ec) {
                    self->lost("cannot write to gportd: " + ec.message());
                    return;
                }
                self->outbox.pop_front();
                if (!self->outbox.empty()) {
                    self->write(generation);
                }
            });
    }

    // Waits for the socket to be readable, then one recvmsg (the bytes and
    // any descriptor gportd attached) and the complete lines.
    void read(std::uint64_t generation) {
        socket.async_wait(Socket::wait_read,
                          [self = shared_from_this(), generation](boost::system::error_code ec) {
                              if (generation != self->current) {
                                  return;
                              }
                              if (ec) {
                                  self->lost("lost gportd: " + ec.message());
                                  return;
                              }
                              if (auto why = self->receive()) {
                                  self->lost(*why);
                                  return;
                              }
                              self->take_lines(generation);
                              if (generation == self->current) {
                                  self->read(generation);
                              }
                          });
    }

    // Why the connection is lost, if it is.
    std::optional<std::string> receive() {
        char chunk[65536];
        const auto n = base::receive_with_descriptors(socket.native_handle(), chunk, sizeof(chunk),
                                                      claims.inbox(), MSG_DONTWAIT);
        claims.received();  // none nobody asked for
        if (n < 0) {
            if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) {
                return std::nullopt;
            }
            return std::string("lost gportd: ") + std::strerror(errno);
        }
        if (n == 0) {
            return std::string("gportd closed the connection");
        }
        input.append(chunk, static_cast<std::size_t>(n));
        return std::nullopt;
    }

    // Handles the complete lines read; a line over a limit or not a JSON
    // object ends the connection.
    void take_lines(std::uint64_t generation) {
        while (generation == current) {
            json message;
            std::string_view text;  // valid until the next read
            try {
                const auto line = input.next();
                if (!line) {
                    return;
                }
                if (detail::blank(*line)) {
                    continue;
                }
                text = *line;
                message = detail::parse_line(text);
            } catch (const Error& e) {
                lost(e.message());
                return;
            }
            handle(message, text);
        }
    }

    // ---- the shared-memory attitude channel ---------------------------------
    // The connection's channel: mapped from its first reply's descriptors,
    // shared by every later one ("descriptors":0).
    void open_channel(Handler<AttitudeChannel> done) {
        std::weak_ptr<Impl> weak = weak_from_this();
        call(contract::method::kAttitudeChannel, json::object(),
             [weak, done = std::move(done)](std::optional<Error> error, const json& reply) {
                 AttitudeChannel channel;
                 const auto self = weak.lock();
                 if (!error && !self) {
                     error = Error(ErrorCode::kTransport, "the client was destroyed");
                 }
                 if (!error) {  // a reply (a lost connection fails the call)
                     try {
                         channel = self->claims.claim(reply);
                     } catch (const Error& e) {
                         error = e;
                     }
                 }
                 done(std::move(error), std::move(channel));
             });
    }

    // Attitude from the ring from now on: the feed's descriptor on the loop.
    void start_ring(AttitudeChannel channel) {
        stop_ring();
        ring = std::make_unique<AttitudeFeed>(std::move(channel));
        ring_wait = std::make_unique<asio::posix::stream_descriptor>(io, ::dup(ring->fd()));
        wait_ring(ring_generation);
    }

    void wait_ring(std::uint64_t generation) {
        std::weak_ptr<Impl> weak = weak_from_this();
        ring_wait->async_wait(asio::posix::stream_descriptor::wait_read,
                              [weak, generation](boost::system::error_code ec) {
                                  const auto self = weak.lock();
                                  if (!self || ec || generation != self->ring_generation) {
                                      return;
                                  }
                                  self->drain_ring(generation);
                                  if (generation == self->ring_generation) {
                                      self->wait_ring(generation);
                                  }
                              });
    }

    // A callback may end the feed (unsubscribe): the generation tells.
    void drain_ring(std::uint64_t generation) {
        ring->reset();
        while (generation == ring_generation) {
            auto sample = ring->take();
            if (!sample) {
                return;
            }
            if (on_notification) {
                on_notification(Notification(std::move(*sample)));
            }
        }
    }

    void stop_ring() {
        ++ring_generation;
        ring_wait.reset();  // a pending wait completes with operation_aborted
        ring.reset();
    }

    void handle(const json& message, std::string_view text) {
        const auto id = message.find("id");
        if (id == message.end()) {
            if (!text.empty() && text.back() == '\r') {
                text.remove_suffix(1);
            }
            if (on_notification_json) {
                on_notification_json(std::string(text));
            }
            if (on_notification_text) {
                const auto method = message.find("method");
                on_notification_text(method != message.end() && method->is_string()
                                         ? method->get<std::string>()
                                         : std::string(),
                                     std::string(text));
            }
            notify(message);
            return;
        }
        if (id->is_number_integer()) {
            if (auto it = pending.find(id->get<int>()); it != pending.end()) {
                auto call = std::move(it->second);
                pending.erase(it);
                call.handler(std::nullopt, message);
            } else {
                claims.late(message);  // its caller gave up: its descriptors are closed
            }
            return;
        }
        if (id->is_null() && message.contains("error")) {  // a refusal before close (-32004)
            try {
                codec::result_of(message);
            } catch (const Error& e) {
                claims.abandon_all();
                fail_pending(e);
            }
        }
    }

    void notify(const json& message) {
        if (on_capture && message.value("method", json()) == "capture") {
            notify_capture(message);
            return;
        }
        if (!on_notification) {
            return;
        }
        std::optional<Notification> n;
        try {
            n = codec::notification(message);
        } catch (const Error&) {
            return;  // a notification this version cannot read: skipped
        }
        if (n) {
            on_notification(*n);
        }
    }

    // The connection broke: every pending call fails, then on_disconnect.
    void lost(const std::string& why) {
        const Error error(ErrorCode::kTransport, why);
        shut(why);
        if (on_disconnect) {
            on_disconnect(error);
        }
    }

    // Closes the socket; pending calls complete with kTransport (posted).
    void shut(const std::string& why) {
        ++current;
        open = false;
        boost::system::error_code ignored;
        socket.close(ignored);
        outbox.clear();
        input.clear();
        claims.reset();
        stop_ring();
        fail_pending(Error(ErrorCode::kTransport, why));
    }

    void fail_pending(const Error& error) {
        auto calls = std::exchange(pending, {});
        for (auto& [id, call] : calls) {
            asio::post(io, [handler = std::move(call.handler), error] { handler(error, json()); });
        }
    }

    // A call waiting for its reply; the timer (none without a call timeout)
    // is cancelled when the call is forgotten.
    struct Pending {
        RawHandler handler;
        std::unique_ptr<asio::steady_timer> timer;
    };

    asio::io_context& io;
    Socket socket;
    detail::LineReader input;
    std::deque<std::pair<int, std::string>> outbox;  // request id, line; the front in flight
    std::map<int, Pending> pending;
    std::optional<std::chrono::milliseconds> call_timeout = kDefaultCallTimeout;
    int next_id = 1;
    std::uint64_t current = 0;  // the connection's generation: stale completions are ignored
    bool open = false;
    std::function<void(const Notification&)> on_notification;
    std::function<void(const std::string&)> on_notification_json;  // each line as read
    // Each line with its method (topic) named (1.9.0).
    std::function<void(const std::string&, const std::string&)> on_notification_text;
    std::function<void(const CaptureEntry&)> on_capture;
    std::function<void(const Error&)> on_disconnect;
    ChannelClaims claims;  // received descriptors, attitude_channel requests, the channel
    // Transparent shared-memory attitude (async_subscribe with shared_memory).
    std::unique_ptr<AttitudeFeed> ring;
    std::unique_ptr<asio::posix::stream_descriptor> ring_wait;
    // The capture topic: beside on_notification, whose Notification variant
    // keeps its alternatives (SOVERSION 1).
    void notify_capture(const json& message) {
        std::optional<CaptureEntry> entry;
        try {
            entry = codec::capture_notification(message);
        } catch (const Error&) {
            return;  // a capture this version cannot read: skipped
        }
        if (entry) {
            on_capture(*entry);
        }
    }

    std::uint64_t ring_generation = 0;
};

namespace {

// Decodes a raw reply into T for a typed handler; the handler itself runs
// outside the try, so that its own exceptions reach io_context::run().
template <typename T, typename Decode>
RawHandler typed(Handler<T> handler, Decode decode) {
    return [handler = std::move(handler), decode](std::optional<Error> error, const json& reply) {
        T value{};
        if (!error) {
            try {
                value = decode(codec::result_of(reply));
            } catch (const Error& e) {
                error = e;
            }
        }
        handler(std::move(error), std::move(value));
    };
}

Done done(const json&) {
    return {};
}

// async_call_json's checks: a method of the contract (attitude_channel
// excepted: its reply carries descriptors) and params that are the text of
// a JSON object (empty text: none); the Error (kInvalidParams) otherwise.
std::optional<Error> json_params(const std::string& method, const std::string& text, json& params) {
    const auto& names = contract::kMethods;
    if (std::find(names.begin(), names.end(), method) == names.end()) {
        return Error(ErrorCode::kInvalidParams, "unknown method '" + method + "'");
    }
    if (method == contract::method::kAttitudeChannel) {
        return Error(ErrorCode::kInvalidParams,
                     "attitude_channel carries descriptors: use async_attitude_channel");
    }
    params =
        json::parse(text.empty() ? std::string_view("{}") : std::string_view(text), nullptr, false);
    if (!params.is_object()) {
        return Error(ErrorCode::kInvalidParams,
                     "params of " + method + " must be the text of a JSON object");
    }
    return std::nullopt;
}

}  // namespace

AsyncClient::AsyncClient(asio::io_context& io) : impl_(std::make_shared<Impl>(io)) {}

AsyncClient::~AsyncClient() {
    impl_->on_notification = nullptr;
    impl_->on_notification_json = nullptr;
    impl_->on_notification_text = nullptr;
    impl_->on_capture = nullptr;
    impl_->on_disconnect = nullptr;
    impl_->shut("the client was destroyed");
}

void AsyncClient::async_connect(const std::string& path,
                                std::function<void(std::optional<Error>)> handler) {
    impl_->connect(path, std::move(handler));
}

void AsyncClient::async_status(Handler<Status> handler) {
    impl_->call(contract::method::kStatus, json::object(),
                typed(std::move(handler), codec::status));
}

void AsyncClient::async_attitude(Handler<AttitudeSample> handler) {
    impl_->call(contract::method::kAttitude, json::object(),
                typed(std::move(handler), codec::attitude));
}

void AsyncClient::async_speed(const Axes& speed, const SpeedOptions& options,
                              Handler<SpeedResult> handler) {
    impl_->call(contract::method::kSpeed, codec::speed_params(speed, options),
                typed(std::move(handler), codec::speed_result));
}

void AsyncClient::async_stop(Handler<Done> handler) {
    impl_->call(contract::method::kStop, json::object(), typed(std::move(handler), done));
}

void AsyncClient::async_angle(const Axes& target, const AngleOptions& options,
                              Handler<AngleResult> handler) {
    impl_->call(contract::method::kAngle, codec::angle_params(target, options),
                typed(std::move(handler), codec::angle_result));
}

void AsyncClient::async_center(const CenterOptions& options, Handler<CenterResult> handler) {
    impl_->call(contract::method::kCenter, codec::center_params(options),
                typed(std::move(handler), codec::center_result));
}

void AsyncClient::async_lock(Handler<Done> handler) {
    impl_->call(contract::method::kLock, json::object(), typed(std::move(handler), done));
}

void AsyncClient::async_publish_vehicle(const VehicleReport& report, Handler<Done> handler) {
    impl_->call(contract::method::kPublishVehicle, codec::vehicle_params(report),
                typed(std::move(handler), done));
}

void AsyncClient::async_photo(Handler<Done> handler) {
    impl_->call(contract::method::kPhoto, json::object(), typed(std::move(handler), done));
}

void AsyncClient::async_record(std::optional<bool> on, bool force, Handler<RecordResult> handler) {
    impl_->call(contract::method::kRecord, codec::record_params(on, force),
                typed(std::move(handler), codec::record_result));
}

void AsyncClient::async_photo(const CaptureOptions& options, Handler<PhotoResult> handler) {
    json params = json::object();
    if (auto error = codec::add_meta(params, options)) {
        asio::post(impl_->io, [handler = std::move(handler), e = *error] { handler(e, {}); });
        return;
    }
    impl_->call(contract::method::kPhoto, params, typed(std::move(handler), codec::photo_result));
}

void AsyncClient::async_photo_report(const CaptureOptions& options, Handler<PhotoReport> handler) {
    json params = json::object();
    if (auto error = codec::add_meta(params, options)) {
        asio::post(impl_->io, [handler = std::move(handler), e = *error] { handler(e, {}); });
        return;
    }
    impl_->call(contract::method::kPhoto, params, typed(std::move(handler), codec::photo_report));
}

void AsyncClient::async_record(std::optional<bool> on, bool force, const CaptureOptions& options,
                               Handler<RecordResult> handler) {
    json params = codec::record_params(on, force);
    if (auto error = codec::add_meta(params, options)) {
        asio::post(impl_->io, [handler = std::move(handler), e = *error] { handler(e, {}); });
        return;
    }
    impl_->call(contract::method::kRecord, params, typed(std::move(handler), codec::record_result));
}

void AsyncClient::async_captures(std::uint64_t since, std::optional<std::uint32_t> limit,
                                 Handler<CapturesPage> handler) {
    impl_->call(contract::method::kCaptures, codec::captures_params(since, limit),
                typed(std::move(handler),
                      [since](const json& result) { return codec::captures_page(result, since); }));
}

void AsyncClient::async_acquire(Handler<Control> handler) {
    impl_->call(contract::method::kAcquire, json::object(),
                typed(std::move(handler), codec::control));
}

void AsyncClient::async_release(Handler<Control> handler) {
    impl_->call(contract::method::kRelease, json::object(),
                typed(std::move(handler), codec::control));
}

void AsyncClient::async_settings(Handler<Settings> handler) {
    impl_->call(contract::method::kGetSettings, json::object(),
                typed(std::move(handler), codec::settings));
}

void AsyncClient::async_limits(Handler<Limits> handler) {
    impl_->call(contract::method::kLimits, json::object(),
                typed(std::move(handler), codec::limits));
}

void AsyncClient::async_set_settings(const SettingsChange& change, Handler<Settings> handler) {
    impl_->call(contract::method::kSetSettings, codec::settings_params(change),
                typed(std::move(handler), codec::settings));
}

void AsyncClient::async_subscribe(const std::vector<std::string>& topics,
                                  std::optional<double> max_rate_hz,
                                  Handler<Subscription> handler) {
    impl_->call(contract::method::kSubscribe, codec::subscribe_params(topics, max_rate_hz),
                typed(std::move(handler), codec::subscription));
}

void AsyncClient::async_subscribe(const std::vector<std::string>& topics,
                                  const SubscribeOptions& options, Handler<Subscription> handler) {
    const bool attitude = std::find(topics.begin(), topics.end(), "attitude") != topics.end();
    if (!options.shared_memory || !attitude) {
        async_subscribe(topics, options.max_rate_hz, std::move(handler));
        return;
    }
    std::vector<std::string> rest;
    std::copy_if(topics.begin(), topics.end(), std::back_inserter(rest),
                 [](const std::string& t) { return t != "attitude"; });
    std::weak_ptr<Impl> weak = impl_;
    impl_->open_channel([weak, rest, handler = std::move(handler)](std::optional<Error> error,
                                                                   AttitudeChannel channel) {
        const auto self = weak.lock();
        if (!error && !self) {
            error = Error(ErrorCode::kTransport, "the client was destroyed");
        }
        if (error) {
            handler(std::move(error), Subscription{});
            return;
        }
        self->start_ring(std::move(channel));
        Handler<Subscription> finish = [handler](std::optional<Error> e, Subscription s) {
            if (!e) {
                s.topics.emplace_back("attitude");
            }
            handler(std::move(e), std::move(s));
        };
        if (rest.empty()) {
            finish(std::nullopt, Subscription{});
            return;
        }
        self->call(contract::method::kSubscribe, codec::subscribe_params(rest, std::nullopt),
                   typed(std::move(finish), codec::subscription));
    });
}

void AsyncClient::async_call_json(const std::string& method, const std::string& params_json,
                                  Handler<std::string> handler) {
    json params;
    if (auto error = json_params(method, params_json, params)) {
        asio::post(impl_->io, [handler = std::move(handler), e = *error] { handler(e, {}); });
        return;
    }
    impl_->call(method, params, typed(std::move(handler), [](const json& result) {
                    return result.dump(-1, ' ', false, json::error_handler_t::replace);
                }));
}

void AsyncClient::async_attitude_channel(Handler<AttitudeChannel> handler) {
    impl_->open_channel(std::move(handler));
}

void AsyncClient::async_unsubscribe(const std::vector<std::string>& topics,
                                    Handler<Subscription> handler) {
    if (topics.empty() || std::find(topics.begin(), topics.end(), "attitude") != topics.end()) {
        impl_->stop_ring();
    }
    impl_->call(contract::method::kUnsubscribe, codec::unsubscribe_params(topics),
                typed(std::move(handler), codec::subscription));
}

void AsyncClient::on_notification(std::function<void(const Notification&)> callback) {
    impl_->on_notification = std::move(callback);
}

void AsyncClient::on_notification_json(std::function<void(const std::string& line)> callback) {
    impl_->on_notification_json = std::move(callback);
}

void AsyncClient::on_notification_text(
    std::function<void(const std::string& method, const std::string& line)> callback) {
    impl_->on_notification_text = std::move(callback);
}

void AsyncClient::on_capture(std::function<void(const CaptureEntry&)> callback) {
    impl_->on_capture = std::move(callback);
}

void AsyncClient::on_disconnect(std::function<void(const Error&)> callback) {
    impl_->on_disconnect = std::move(callback);
}

void AsyncClient::close() {
    impl_->shut("closed by the client");
}

bool AsyncClient::connected() const noexcept {
    return impl_->open;
}

void AsyncClient::set_call_timeout(std::optional<Milliseconds> timeout) {
    impl_->call_timeout = timeout;
}

std::optional<Milliseconds> AsyncClient::call_timeout() const {
    return impl_->call_timeout;
}

}  // namespace gport::client
