// The blocking client: Connection for the transport, codec for the JSON.
#include "gport/client/client.hpp"

#include <algorithm>
#include <cstdlib>
#include <iterator>
#include <utility>

#include "attitude_feed.hpp"
#include "codec.hpp"
#include "connection.hpp"
#include "gport/base/json_depth.hpp"
#include "gport/contract/names.hpp"
#include "notification_queue.hpp"

namespace gport::client {

using nlohmann::json;

namespace {

// call_json's checks: the API's method syntax, params that are a JSON object
// or array within the nesting limit (empty: none).
json json_request_params(const std::string& method, const std::string& text) {
    const bool name_ok = !method.empty() && method.size() <= 64 &&
                         std::all_of(method.begin(), method.end(), [](char c) {
                             return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                                    (c >= '0' && c <= '9') || c == '_' || c == '.';
                         });
    if (!name_ok) {
        throw Error(ErrorCode::kInvalidParams,
                    "a method name is 1 to 64 letters, digits, '_' and '.'; nothing was sent");
    }
    if (text.empty()) {
        return json();
    }
    if (base::nested_deeper_than(text, kNestingLimit)) {
        throw Error(ErrorCode::kInvalidParams, "params of " + method + " nested deeper than " +
                                                   std::to_string(kNestingLimit) +
                                                   " levels; nothing was sent");
    }
    json params = json::parse(text, nullptr, false);
    if (!params.is_object() && !params.is_array()) {
        throw Error(ErrorCode::kInvalidParams, "params of " + method +
                                                   " must be a JSON object or array; nothing "
                                                   "was sent");
    }
    return params;
}

}  // namespace

struct Client::Impl {
    explicit Impl(Connection c) : connection(std::move(c)) {}

    // Calls a method; notifications meanwhile are kept or handed on.
    json call(const std::string& method, const json& params = json::object()) {
        return codec::result_of(call_raw(method, params));
    }

    // The same, returning the whole reply (the result or gportd's error).
    json call_raw(const std::string& method, const json& params = json::object()) {
        if (connection.closed()) {
            throw Error(ErrorCode::kTransport, "not connected to gportd (connect again)");
        }
        auto reply = connection.call(method, params, [this](const json& m) { take(m); });
        if (!reply && !connection.closed() && connection.interrupted()) {
            throw Error(ErrorCode::kInterrupted, "interrupted while waiting for the reply to " +
                                                     method + " (a late reply is dropped)");
        }
        if (!reply) {
            connection.close();
            throw lost("the connection to gportd was lost during " + method);
        }
        if (callback) {
            drain_ring(false);  // ring samples reach the callback during calls too
        }
        return *reply;
    }

    // call_json_response: any method with params as text; the whole reply.
    json json_response(const std::string& method, const std::string& params_json) {
        json reply = call_raw(method, json_request_params(method, params_json));
        if (method == contract::method::kAttitudeChannel && reply.contains("result")) {
            try {
                connection.channel_from(reply);  // its descriptors: claimed and closed
            } catch (const Error&) {             // a block that fails its checks: none kept
            }
        }
        return reply;
    }

    // Hands a notification to the callback, or queues it (always, when
    // `queue_only`: next_notification() returns it). One this version cannot
    // read is skipped rather than failing the call that received it.
    void take(const json& message, bool queue_only = false) {
        if (json_callback) {
            json_callback(message.dump(-1, ' ', false, json::error_handler_t::replace));
        }
        if (message.value("method", json()) == "capture") {
            take_capture(message);
            return;
        }
        std::optional<Notification> n;
        try {
            n = codec::notification(message);
        } catch (const Error&) {
            return;
        }
        if (!n) {
            return;
        }
        if (callback && !queue_only) {
            callback(*n);
        } else {
            queue.push(std::move(*n));
        }
    }

    // The capture topic goes to its own callback (skipped without one).
    void take_capture(const json& message) const {
        if (!capture_callback) {
            return;
        }
        std::optional<CaptureEntry> entry;
        try {
            entry = codec::capture_notification(message);
        } catch (const Error&) {
            return;
        }
        if (entry) {
            capture_callback(*entry);
        }
    }

    // The transport Error for a lost connection: why the library ended it,
    // if it did.
    Error lost(const std::string& otherwise) const {
        const auto& why = connection.failure();
        return Error(ErrorCode::kTransport, why.empty() ? otherwise : why);
    }

    // Reads one message (or the ring's new samples) within the timeout;
    // returns how many notifications came.
    std::size_t read_one(std::optional<Milliseconds> timeout, bool queue_only) {
        if (connection.closed()) {
            throw Error(ErrorCode::kTransport, "not connected to gportd (connect again)");
        }
        json message;
        const auto status = connection.read(message, timeout);
        if (status == Connection::ReadStatus::kClosed) {
            stop_ring();
            connection.close();
            throw lost("gportd closed the connection");
        }
        if (status == Connection::ReadStatus::kWoken) {
            return drain_ring(queue_only);
        }
        if (status == Connection::ReadStatus::kInterrupted) {
            throw Error(ErrorCode::kInterrupted, "interrupted while waiting for notifications");
        }
        if (status != Connection::ReadStatus::kMessage) {
            return 0;
        }
        if (!message.contains("id")) {
            take(message, queue_only);
        } else if (message["id"].is_null()) {
            codec::result_of(message);  // a refusal before close (e.g. -32004 idle): throws
        }
        return 1;
    }

    // ---- the shared-memory attitude channel ---------------------------------
    // The connection's channel: mapped from its first reply's descriptors,
    // shared by every later one.
    AttitudeChannel open_channel() {
        return connection.channel_from(call_raw(contract::method::kAttitudeChannel));
    }

    // Attitude from the ring from now on, woken through the connection's poll.
    void start_ring() {
        if (!ring) {
            ring = std::make_unique<AttitudeFeed>(open_channel());
            connection.watch(ring->fd());
        }
    }

    void stop_ring() noexcept {
        connection.watch(-1);
        ring.reset();
    }

    // A callback may end the feed (unsubscribe): looked at before each take.
    std::size_t drain_ring(bool queue_only) {
        if (!ring) {
            return 0;
        }
        ring->reset();
        std::size_t count = 0;
        while (ring) {
            auto sample = ring->take();
            if (!sample) {
                break;
            }
            ++count;
            if (json_callback) {
                json_callback(attitude_notification(*sample).dump());
            }
            if (callback && !queue_only) {
                callback(Notification(std::move(*sample)));
            } else {
                queue.push(Notification(std::move(*sample)));
            }
        }
        return count;
    }

    Connection connection;
    detail::NotificationQueue queue;
    std::function<void(const Notification&)> callback;
    std::function<void(const CaptureEntry&)> capture_callback;  // the capture topic
    std::function<void(const std::string&)> json_callback;      // every notification as text
    // Transparent shared-memory attitude (subscribe with shared_memory).
    std::unique_ptr<AttitudeFeed> ring;
};

std::string Client::default_socket() {
    return default_socket(std::getenv(kSocketEnv));
}

std::string Client::default_socket(const char* env_value) {
    return env_value != nullptr && *env_value != '\0' ? std::string(env_value)
                                                      : std::string(kDefaultSocket);
}

Client Client::connect(const std::string& path) {
    return Client(std::make_unique<Impl>(Connection::open(path)));
}

Client::Client(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Client::Impl& Client::impl() {
    if (!impl_) {
        throw Error(ErrorCode::kTransport, "this Client was moved from; connect a new one");
    }
    return *impl_;
}
Client::Client(Client&& other) noexcept = default;
Client& Client::operator=(Client&& other) noexcept = default;
Client::~Client() = default;

Status Client::status() {
    return codec::status(impl().call(contract::method::kStatus));
}
AttitudeSample Client::attitude() {
    return codec::attitude(impl().call(contract::method::kAttitude));
}

SpeedResult Client::speed(const Axes& speed, std::optional<Milliseconds> duration,
                          std::optional<Milliseconds> lease, bool clamp) {
    return this->speed(speed, SpeedOptions{duration, lease, clamp});
}

SpeedResult Client::speed(const Axes& speed, const SpeedOptions& options) {
    return codec::speed_result(
        impl().call(contract::method::kSpeed, codec::speed_params(speed, options)));
}

void Client::stop() {
    impl().call(contract::method::kStop);
}

AngleResult Client::angle(const Axes& target, const AngleOptions& options) {
    return codec::angle_result(
        impl().call(contract::method::kAngle, codec::angle_params(target, options)));
}

CenterResult Client::center(const CenterOptions& options) {
    return codec::center_result(
        impl().call(contract::method::kCenter, codec::center_params(options)));
}

void Client::lock() {
    impl().call(contract::method::kLock);
}
void Client::publish_vehicle(const VehicleReport& report) {
    impl().call(contract::method::kPublishVehicle, codec::vehicle_params(report));
}

void Client::photo() {
    impl().call(contract::method::kPhoto);
}

RecordResult Client::record() {
    return codec::record_result(
        impl().call(contract::method::kRecord, codec::record_params(std::nullopt, false)));
}

RecordResult Client::record(bool on, bool force) {
    return codec::record_result(
        impl().call(contract::method::kRecord, codec::record_params(on, force)));
}

PhotoReport Client::photo(const CaptureOptions& options) {
    json params = json::object();
    if (auto error = codec::add_meta(params, options)) {
        throw *error;
    }
    return codec::photo_report(impl().call(contract::method::kPhoto, params));
}

RecordResult Client::record(std::optional<bool> on, bool force, const CaptureOptions& options) {
    json params = codec::record_params(on, force);
    if (auto error = codec::add_meta(params, options)) {
        throw *error;
    }
    return codec::record_result(impl().call(contract::method::kRecord, params));
}

CapturesPage Client::captures(std::uint64_t since, std::optional<std::uint32_t> limit) {
    return codec::captures_page(
        impl().call(contract::method::kCaptures, codec::captures_params(since, limit)), since);
}

void Client::on_capture(std::function<void(const CaptureEntry&)> callback) {
    impl().capture_callback = std::move(callback);
}

Control Client::acquire() {
    return codec::control(impl().call(contract::method::kAcquire));
}
Control Client::release() {
    return codec::control(impl().call(contract::method::kRelease));
}
Limits Client::limits() {
    return codec::limits(impl().call(contract::method::kLimits));
}
Settings Client::settings() {
    return codec::settings(impl().call(contract::method::kGetSettings));
}

Settings Client::set_settings(const SettingsChange& change) {
    return codec::settings(
        impl().call(contract::method::kSetSettings, codec::settings_params(change)));
}

Subscription Client::subscribe(const std::vector<std::string>& topics,
                               std::optional<double> max_rate_hz) {
    return codec::subscription(
        impl().call(contract::method::kSubscribe, codec::subscribe_params(topics, max_rate_hz)));
}

Subscription Client::subscribe(const std::vector<std::string>& topics,
                               const SubscribeOptions& options) {
    const bool attitude = std::find(topics.begin(), topics.end(), "attitude") != topics.end();
    if (!options.shared_memory || !attitude) {
        return subscribe(topics, options.max_rate_hz);
    }
    auto& impl = this->impl();
    std::vector<std::string> rest;
    std::copy_if(topics.begin(), topics.end(), std::back_inserter(rest),
                 [](const std::string& t) { return t != "attitude"; });
    Subscription result;
    if (!rest.empty()) {
        result = codec::subscription(
            impl.call(contract::method::kSubscribe, codec::subscribe_params(rest, std::nullopt)));
    }
    impl.start_ring();
    result.topics.emplace_back("attitude");
    return result;
}

Subscription Client::unsubscribe(const std::vector<std::string>& topics) {
    auto& impl = this->impl();
    if (topics.empty() || std::find(topics.begin(), topics.end(), "attitude") != topics.end()) {
        impl.stop_ring();
    }
    return codec::subscription(
        impl.call(contract::method::kUnsubscribe, codec::unsubscribe_params(topics)));
}

AttitudeChannel Client::attitude_channel() {
    return impl().open_channel();
}

std::optional<Notification> Client::next_notification(std::optional<Milliseconds> timeout) {
    auto& impl = this->impl();
    // Used only with a timeout (always set: g++ -O1 took an optional
    // deadline for one that may be read unset).
    const auto deadline = std::chrono::steady_clock::now() + timeout.value_or(Milliseconds(0));
    bool tried = false;  // a zero timeout still reads what already arrived
    while (impl.queue.empty()) {
        std::optional<Milliseconds> left;
        if (timeout) {
            left = std::max(Milliseconds(0), std::chrono::duration_cast<Milliseconds>(
                                                 deadline - std::chrono::steady_clock::now()));
            if (tried && left->count() == 0) {
                return std::nullopt;
            }
        }
        impl.read_one(left, true);
        tried = true;
    }
    return impl.queue.pop();
}

void Client::on_notification(std::function<void(const Notification&)> callback) {
    auto& impl = this->impl();
    impl.callback = std::move(callback);
    while (impl.callback && !impl.queue.empty()) {
        impl.callback(*impl.queue.pop());
    }
}

std::size_t Client::dispatch(Milliseconds duration) {
    auto& impl = this->impl();
    std::size_t count = 0;
    const auto deadline = std::chrono::steady_clock::now() + duration;
    while (true) {
        const auto left =
            std::chrono::duration_cast<Milliseconds>(deadline - std::chrono::steady_clock::now());
        if (left.count() <= 0) {
            return count;
        }
        try {
            count += impl.read_one(left, false);
        } catch (const Error& e) {
            if (e.is(ErrorCode::kInterrupted)) {
                return count;
            }
            throw;
        }
    }
}

std::string Client::call_json_response(const std::string& method, const std::string& params_json) {
    return impl()
        .json_response(method, params_json)
        .dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string Client::call_json(const std::string& method, const std::string& params_json) {
    return codec::result_of(impl().json_response(method, params_json))
        .dump(-1, ' ', false, json::error_handler_t::replace);
}

void Client::on_notification_json(std::function<void(const std::string& json)> callback) {
    impl().json_callback = std::move(callback);
}

void Client::set_interrupt(std::function<bool()> interrupted) {
    impl().connection.interrupted =
        interrupted ? std::move(interrupted) : std::function<bool()>([] { return false; });
}

void Client::close() {
    if (impl_) {
        impl_->stop_ring();
        impl_->connection.close();
    }
}

bool Client::connected() const noexcept {
    return impl_ && !impl_->connection.closed();
}

void Client::set_call_timeout(std::optional<Milliseconds> timeout) {
    impl().connection.set_call_timeout(timeout);
}

std::optional<Milliseconds> Client::call_timeout() const {
    if (!impl_) {
        throw Error(ErrorCode::kTransport, "this Client was moved from; connect a new one");
    }
    return impl_->connection.call_timeout();
}

std::uint64_t Client::dropped_notifications() const noexcept {
    return impl_ ? impl_->queue.dropped() : 0;
}

}  // namespace gport::client
