// gport::client::Client: a blocking connection to gportd with one typed call
// per method of docs/api.md.
//
//     auto gimbal = gport::client::Client::connect();
//     gimbal.angle({.pitch = -30, .yaw = 45}, {.wait = true});
//     gimbal.photo();
//
// Errors: every call throws gport::client::Error (error.hpp): the daemon's
// code and message, ErrorCode::kTransport when the connection is gone
// (then connect again; gportd may have restarted), ErrorCode::kTimeout when
// no reply came within the call timeout (set_call_timeout).
//
// Limits (limits.hpp): a line from gportd over kLineLimit or nested deeper
// than kNestingLimit, or not a JSON object, ends the connection (kTransport
// naming it); at most kNotificationQueueLimit notifications of each kind
// wait for next_notification(), the oldest beyond that are dropped and
// counted (dropped_notifications()).
//
// Notifications: after subscribe(), samples and events arriving during any
// call are kept in order; take them with next_notification(), or set a
// callback with on_notification() and let dispatch() (or any call) deliver
// them.
//
// Thread-safety: a Client is not synchronised. Use one Client per thread
// (or guard one with a mutex); distinct Clients are independent. Callbacks
// run on the thread that made the call, inside that call; an exception from
// a callback leaves that call (its reply is then lost).
#pragma once

#include <chrono>
#include <cstdint>
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
#include "gport/contract/names.hpp"

namespace gport::client {

class GPORT_CLIENT_API Client {
  public:
    // The wire contract's (gport/contract/names.hpp).
    static constexpr const char* kDefaultSocket = contract::kDefaultSocket;
    static constexpr const char* kSocketEnv = contract::kSocketEnv;

    // $GPORT_SOCKET when set and not empty, else kDefaultSocket.
    static std::string default_socket();
    // The same rule for a value of $GPORT_SOCKET the caller read (null:
    // unset), so that every program says it once (1.9.0).
    static std::string default_socket(const char* env_value);
    // Connects to gportd's socket; throws Error (kTransport) when it cannot.
    static Client connect(const std::string& path = default_socket());

    Client(Client&& other) noexcept;
    Client& operator=(Client&& other) noexcept;
    Client(const Client&) = delete;
    Client& operator=(const Client&) = delete;
    ~Client();

    Status status();
    AttitudeSample attitude();
    SpeedResult speed(const Axes& speed, std::optional<Milliseconds> duration = std::nullopt,
                      std::optional<Milliseconds> lease = std::nullopt, bool clamp = false);
    SpeedResult speed(const Axes& speed, const SpeedOptions& options);
    void stop();
    AngleResult angle(const Axes& target, const AngleOptions& options = {});
    CenterResult center(const CenterOptions& options = {});
    void lock();
    void photo();
    RecordResult record();  // one toggle
    RecordResult record(bool on, bool force = false);
    // With `meta` (CaptureOptions; not a JSON object: kInvalidParams, nothing
    // sent): the capture gportd logged and its attitude (1.5.0).
    PhotoReport photo(const CaptureOptions& options);
    // `on` empty: one toggle. `capture` is empty when nothing was sent (1.5.0).
    RecordResult record(std::optional<bool> on, bool force, const CaptureOptions& options);
    // One page of the capture log from index `since` (1.5.0): at most `limit`
    // (gportd's default when empty) and 64 KiB; page on with `next` while
    // `more`.
    CapturesPage captures(std::uint64_t since = 0,
                          std::optional<std::uint32_t> limit = std::nullopt);
    // The vehicle's state for gportd to stamp captures with (1.10.0; only a
    // trusted source may: kPermission otherwise).
    void publish_vehicle(const VehicleReport& report);
    Control acquire();
    Control release();
    Settings settings();
    Settings set_settings(const SettingsChange& change);
    Limits limits();  // gportd's configured soft limits

    // topics: "attitude", "link", "motion", "capture" (on_capture); max_rate_hz
    // caps attitude.
    Subscription subscribe(const std::vector<std::string>& topics,
                           std::optional<double> max_rate_hz = std::nullopt);
    // With options.shared_memory and "attitude" among the topics, attitude
    // samples come from the shared-memory channel (opened here) instead of
    // the socket, as AttitudeSample notifications like the socket's (only
    // samples published after this call; `dropped` counts the skipped
    // ones). A waiter thread turns the channel's wakes into a descriptor
    // that next_notification() and dispatch() poll with the socket.
    Subscription subscribe(const std::vector<std::string>& topics, const SubscribeOptions& options);
    // No topics: all (also ends the shared-memory attitude delivery).
    Subscription unsubscribe(const std::vector<std::string>& topics = {});

    // Any method with its params as JSON text, for tools that pass JSON
    // through (gportctl call and --json) (1.6.0). `method`: 1 to 64 of
    // [A-Za-z0-9_.] (gportd answers one it does not know with -32601);
    // `params_json`: the text of a JSON object or array, nested at most
    // kNestingLimit (empty: none). Anything else: kInvalidParams naming what
    // was wrong, nothing sent. call_json returns gportd's `result` as JSON
    // text and throws gportd's error like the typed calls;
    // call_json_response returns the whole response (`id` and `result` or
    // `error`) and throws only kTransport, kTimeout and kInterrupted.
    std::string call_json(const std::string& method, const std::string& params_json = {});
    std::string call_json_response(const std::string& method, const std::string& params_json = {});
    // Every notification as JSON text, in arrival order, whenever a call,
    // dispatch() or next_notification() reads (1.6.0): a line from gportd
    // as it came (the whole object), a shared-memory attitude sample as the
    // socket would have carried it. In addition to on_notification and
    // on_capture, not instead; an empty function turns it off.
    void on_notification_json(std::function<void(const std::string& json)> callback);
    // A check looked at while a call, dispatch() or next_notification()
    // waits: at least every 100 ms, and at once when a signal handled
    // without SA_RESTART interrupts the wait (1.6.0). Once it returns true
    // the waiting call throws Error kInterrupted (its reply, if it comes, is
    // dropped) and dispatch() returns; the connection stays usable, unless
    // the check cut a request in half (then kTransport).
    void set_interrupt(std::function<bool()> interrupted);

    // Opens gportd's shared-memory attitude channel (docs/api.md); throws
    // Error: the daemon's (e.g. -32603 when it cannot make the block), or
    // kBadReply when the block fails its checks (the message names why).
    AttitudeChannel attitude_channel();

    // The next notification, waiting at most `timeout` (forever when empty);
    // empty on timeout. Throws Error (kTransport) when the connection breaks.
    std::optional<Notification> next_notification(
        std::optional<Milliseconds> timeout = std::nullopt);
    // With a callback set, notifications go to it instead of the queue
    // (kept ones first); an empty function goes back to queueing.
    void on_notification(std::function<void(const Notification&)> callback);
    // Each capture after subscribe({"capture"}) (1.5.0), delivered when
    // notifications are (dispatch(), next_notification(), any call): the
    // topic comes here, never to the Notification queue, whose variant keeps
    // its three kinds; without a callback captures are skipped.
    void on_capture(std::function<void(const CaptureEntry&)> callback);
    // Reads for `duration` and hands notifications to the callback (or the
    // queue); returns how many arrived.
    std::size_t dispatch(Milliseconds duration);

    // Closes the connection (also done by the destructor): gportd then
    // stops this client's motion and releases its control.
    void close();
    bool connected() const noexcept;

    // The longest wait for a call's reply (kDefaultCallTimeout unless set;
    // empty: no limit); calls with `wait` get kWaitAllowance more. After it
    // the call throws kTimeout and the connection stays usable (a late reply
    // is dropped). gportd not reading a request for that long closes the
    // connection (kTransport).
    void set_call_timeout(std::optional<Milliseconds> timeout);
    std::optional<Milliseconds> call_timeout() const;
    // Notifications dropped because nobody took them (the queue of their
    // kind held kNotificationQueueLimit); not gportd's own `dropped`.
    std::uint64_t dropped_notifications() const noexcept;

  private:
    struct Impl;
    explicit Client(std::unique_ptr<Impl> impl);
    Impl& impl();  // throws kTransport on a moved-from Client
    std::unique_ptr<Impl> impl_;
};

}  // namespace gport::client
