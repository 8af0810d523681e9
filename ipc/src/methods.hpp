// The method table: one short handler per JSON-RPC method, found by name.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

#include "gport/ipc/json_rpc.hpp"
#include "gport/ipc/status_cache.hpp"

namespace gport::ipc::detail {

// A method's answer: a result (a JSON value, or text already serialized:
// the cached part of `status`, spliced) or an error. Serialized when made,
// so the reply object is built from text alone.
class Reply {
  public:
    Reply(const nlohmann::json& result);  // NOLINT(google-explicit-constructor): respond(json{...})
    static Reply error(int code, std::string message);
    static Reply raw(std::string result_text);

    // The JSON-RPC reply object for `id`, serialized, without a newline;
    // members in the order nlohmann writes them (sorted), whatever the form.
    std::string object(const nlohmann::json& id) const;

  private:
    Reply() = default;
    std::string text_;  // the result, serialized; or the error's message
    std::optional<int> error_code_;
};

// Called exactly once per call, possibly later (settings).
using Respond = std::function<void(Reply)>;

struct MethodContext {
    daemon::Api& api;
    ClientState& client;
    const std::function<ServerStats()>& stats;
    StatusCache& status_cache;
    ChannelHost* channel;  // nullptr: the attitude channel is not served
    capture::CaptureLog& captures;
    // The request running is a notification: its reply is never sent.
    bool notification = false;
    // Where the time each request holds the loop is kept (nullptr: not kept).
    Dispatcher::Worst* worst = nullptr;
};

using Handler = void (*)(MethodContext& context, const nlohmann::json& params, Respond respond);

// nullptr for an unknown method.
Handler find_method(std::string_view name);
// "status, attitude, ..." for the unknown-method message.
std::string method_list();

}  // namespace gport::ipc::detail
