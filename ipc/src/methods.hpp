// The method table: one short handler per JSON-RPC method, found by name.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <variant>

#include "gport/ipc/json_rpc.hpp"
#include "gport/ipc/status_cache.hpp"

namespace gport::ipc::detail {

struct RpcError {
    int code = 0;
    std::string message;
};

// A result already serialized (the cached part of `status`, spliced).
struct RawJson {
    std::string text;
};

// A result whose reply line may carry the attitude channel's descriptors.
struct ChannelResult {
    nlohmann::json result;
    std::size_t descriptors = 0;  // 2 or 0
};

// A method's answer: its result, or an error.
using Reply = std::variant<nlohmann::json, RpcError, RawJson, ChannelResult>;
// Called exactly once per call, possibly later (settings).
using Respond = std::function<void(Reply)>;

struct MethodContext {
    daemon::Api& api;
    ClientState& client;
    const std::function<ServerStats()>& stats;
    StatusCache& status_cache;
    ChannelHost* channel;  // nullptr: the attitude channel is not served
    CaptureLog& captures;
    // The request running is a notification: its reply is never sent.
    bool notification = false;
};

using Handler = void (*)(MethodContext& context, const nlohmann::json& params, Respond respond);

// nullptr for an unknown method.
Handler find_method(std::string_view name);
// "status, attitude, ..." for the unknown-method message.
std::string method_list();

}  // namespace gport::ipc::detail
