// gport::client::AsyncClient: the asynchronous client, on a Boost.Asio
// io_context the caller runs. Same methods and types as Client (client.hpp);
// each takes a completion handler called with (error, result): `error` is
// empty on success, else the daemon's error, kTransport or kTimeout.
//
//     boost::asio::io_context io;
//     gport::client::AsyncClient gimbal(io);
//     gimbal.async_connect(path, [&](auto error) {
//         gimbal.async_status([](auto error, gport::client::Status s) { ... });
//     });
//     io.run();
//
// Limits (limits.hpp), as Client's: a line over kLineLimit, nested deeper
// than kNestingLimit or not a JSON object ends the connection (pending
// calls get kTransport naming it, then on_disconnect); a call whose reply
// does not come within the call timeout completes with kTimeout.
//
// Handlers and the notification callback run on the io_context's thread,
// from io.run(); they are never called from inside the initiating call.
// Thread-safety: use an AsyncClient only from its io_context's thread (run
// the io_context on one thread, or post to it). Destroying the AsyncClient
// or close() completes the pending calls with kTransport.
//
// Built against the Boost 1.74 headers: compile with the same Boost.
#pragma once

#include <boost/asio/io_context.hpp>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gport/client/attitude_channel.hpp"
#include "gport/client/error.hpp"
#include "gport/client/export.hpp"
#include "gport/client/limits.hpp"
#include "gport/client/types.hpp"

namespace gport::client {

// The completion of a call without a result value (stop, lock, photo).
struct Done {};

template <typename T>
using Handler = std::function<void(std::optional<Error> error, T result)>;

class GPORT_CLIENT_API AsyncClient {
  public:
    explicit AsyncClient(boost::asio::io_context& io);
    AsyncClient(const AsyncClient&) = delete;
    AsyncClient& operator=(const AsyncClient&) = delete;
    ~AsyncClient();

    // Connects (closing any earlier connection); the handler gets kTransport
    // when gportd cannot be reached.
    void async_connect(const std::string& path,
                       std::function<void(std::optional<Error> error)> handler);

    void async_status(Handler<Status> handler);
    void async_attitude(Handler<AttitudeSample> handler);
    void async_speed(const Axes& speed, const SpeedOptions& options, Handler<SpeedResult> handler);
    void async_stop(Handler<Done> handler);
    void async_angle(const Axes& target, const AngleOptions& options, Handler<AngleResult> handler);
    void async_center(const CenterOptions& options, Handler<CenterResult> handler);
    void async_lock(Handler<Done> handler);
    void async_photo(Handler<Done> handler);
    void async_record(std::optional<bool> on, bool force, Handler<RecordResult> handler);
    // With `meta` (CaptureOptions) and the capture gportd logged. A meta
    // that is no JSON object completes with kInvalidParams, nothing sent.
    void async_photo(const CaptureOptions& options, Handler<PhotoResult> handler);
    // The same with the attitude gportd logged for the capture (1.4.0).
    void async_photo_report(const CaptureOptions& options, Handler<PhotoReport> handler);
    void async_record(std::optional<bool> on, bool force, const CaptureOptions& options,
                      Handler<RecordResult> handler);
    // One page of the capture log from index `since` (1.5.0): at most `limit`
    // (gportd's default when empty) and 64 KiB; page on with `next` while
    // `more`.
    void async_captures(std::uint64_t since, std::optional<std::uint32_t> limit,
                        Handler<CapturesPage> handler);
    // The vehicle's state for gportd to stamp captures with (1.10.0); only a
    // trusted source may (kPermission otherwise; docs/api.md, "The vehicle").
    void async_publish_vehicle(const VehicleReport& report, Handler<Done> handler);
    void async_acquire(Handler<Control> handler);
    void async_release(Handler<Control> handler);
    void async_settings(Handler<Settings> handler);
    void async_set_settings(const SettingsChange& change, Handler<Settings> handler);
    void async_limits(Handler<Limits> handler);
    void async_subscribe(const std::vector<std::string>& topics, std::optional<double> max_rate_hz,
                         Handler<Subscription> handler);
    // With options.shared_memory and "attitude" among the topics, attitude
    // comes from the shared-memory channel (as Client::subscribe): a waiter
    // thread makes an eventfd readable per sample and the io_context's
    // thread hands the samples to on_notification.
    void async_subscribe(const std::vector<std::string>& topics, const SubscribeOptions& options,
                         Handler<Subscription> handler);
    // No topics: all (also ends the shared-memory attitude delivery).
    void async_unsubscribe(const std::vector<std::string>& topics, Handler<Subscription> handler);
    // Opens gportd's shared-memory attitude channel (Client::attitude_channel).
    void async_attitude_channel(Handler<AttitudeChannel> handler);
    // Any method of contract::kMethods (gport/contract/names.hpp) with its
    // params as the text of a JSON object (empty text: no params); the
    // handler gets gportd's `result` as JSON text (1.6.0). An unknown
    // method, attitude_channel (use async_attitude_channel) or params that
    // are not a JSON object complete with kInvalidParams naming what was
    // wrong, nothing sent. Replies and timeouts as for the typed calls.
    void async_call_json(const std::string& method, const std::string& params_json,
                         Handler<std::string> handler);

    // Every notification, in arrival order.
    void on_notification(std::function<void(const Notification&)> callback);
    // Every notification line read from gportd's socket, as gportd wrote it
    // (the whole {"jsonrpc":..,"method":..,"params":..} object, without its
    // newline), in arrival order, before on_notification and on_capture get
    // it; in addition to them, not instead (1.6.0). Attitude samples from
    // the shared-memory channel are not lines: they come to on_notification
    // only.
    void on_notification_json(std::function<void(const std::string& line)> callback);
    // The same lines with their method (the topic: "attitude", "link",
    // "motion", "capture", ...), read once by the library, so that a relay
    // routes a line without searching its text (1.9.0).
    void on_notification_text(
        std::function<void(const std::string& method, const std::string& line)> callback);
    // Each capture after subscribing to "capture" (1.5.0): the topic's
    // notifications come here, not to on_notification (whose Notification
    // keeps its three kinds); without a callback they are skipped.
    void on_capture(std::function<void(const CaptureEntry&)> callback);
    // Called once when an open connection breaks (not on close()).
    void on_disconnect(std::function<void(const Error&)> callback);

    void close();
    bool connected() const noexcept;

    // The longest wait for a call's reply (kDefaultCallTimeout unless set;
    // empty: no limit), for the calls made from now on; calls with `wait`
    // get kWaitAllowance more. After it the handler gets kTimeout and the
    // connection stays (a late reply is dropped); when gportd has not even
    // read the request by then, the connection is closed (kTransport).
    void set_call_timeout(std::optional<Milliseconds> timeout);
    std::optional<Milliseconds> call_timeout() const;

  private:
    struct Impl;
    std::shared_ptr<Impl> impl_;
};

}  // namespace gport::client
