// Request lines to replies: envelope checks, batches, and dispatch through
// the method table. Everything a client controls is checked here before any
// method runs.
#include "gport/ipc/json_rpc.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <memory>
#include <utility>
#include <vector>

#include "gport/base/json_depth.hpp"
#include "gport/daemon/client_log.hpp"
#include "json_common.hpp"
#include "methods.hpp"
#include "params.hpp"

namespace gport::ipc {
namespace {

using detail::Reply;
using nlohmann::json;

std::string dump(const json& value) {
    return detail::json_text(value);
}

json error_object(const json& id, int code, std::string_view message) {
    return {{"jsonrpc", "2.0"},
            {"id", id},
            {"error", {{"code", code}, {"message", std::string(message)}}}};
}

// Checks the envelope; an error is the reply to send (with id null when the
// id itself was unusable).
std::optional<json> envelope_error(const json& request) {
    if (!request.is_object()) {
        return error_object(nullptr, rpc_error::kInvalidRequest, "a request must be a JSON object");
    }
    for (const auto& [key, value] : request.items()) {
        if (key != "jsonrpc" && key != "id" && key != "method" && key != "params") {
            return error_object(nullptr, rpc_error::kInvalidRequest,
                                "unknown request member; allowed: jsonrpc, id, method and params");
        }
    }
    auto id = request.find("id");
    if (id != request.end()) {
        if (!id->is_null() && !id->is_number() && !id->is_string()) {
            return error_object(nullptr, rpc_error::kInvalidRequest,
                                "id must be a number, a string or null");
        }
        if (id->is_string() && id->get_ref<const std::string&>().size() > kMaxIdLength) {
            return error_object(nullptr, rpc_error::kInvalidRequest,
                                fmt::format("id strings are limited to {} bytes", kMaxIdLength));
        }
    }
    const json id_value = id == request.end() ? json(nullptr) : *id;
    auto version = request.find("jsonrpc");
    if (version != request.end() && *version != "2.0") {
        return error_object(id_value, rpc_error::kInvalidRequest,
                            R"(jsonrpc must be "2.0" when given)");
    }
    auto method = request.find("method");
    if (method == request.end() || !method->is_string()) {
        return error_object(id_value, rpc_error::kInvalidRequest, "method must be a string");
    }
    return std::nullopt;
}

std::string unknown_method(const std::string& name) {
    std::string shown = name.size() > 64 ? name.substr(0, 64) + "..." : name;
    return fmt::format("unknown method \"{}\"; methods: {}", shown, detail::method_list());
}

std::string over_rate(const RequestRate& rate) {
    return fmt::format(
        "too many requests: the limit is {} per second (socket.max_requests_per_s); slow down",
        rate.per_second());
}

void run_method(detail::Handler handler, detail::MethodContext& context, const json& params,
                const detail::Respond& respond) {
    try {
        handler(context, params, respond);
    } catch (const detail::InvalidParams& e) {
        respond(Reply::error(rpc_error::kInvalidParams, e.what()));
    } catch (const std::exception& e) {
        // A bug, not bad input: report it rather than drop the connection.
        respond(Reply::error(rpc_error::kInternal, fmt::format("internal error: {}", e.what())));
    }
}

// `done` receives the reply object, serialized (no newline), or is not
// called at all for a notification.
void run_request(const json& request, detail::MethodContext& context, const ReplySink& done) {
    if (auto error = envelope_error(request)) {
        done(dump(*error));
        return;
    }
    const auto id_it = request.find("id");
    const bool notification = id_it == request.end();
    const json id = notification ? json(nullptr) : *id_it;
    detail::Respond respond = [done, id, notification](const Reply& reply) {
        if (!notification) {
            done(reply.object(id));
        }
    };
    if (!context.client.rate.take(std::chrono::steady_clock::now())) {
        respond(Reply::error(rpc_error::kTooManyRequests, over_rate(context.client.rate)));
        return;
    }
    const auto& name = request["method"].get_ref<const std::string&>();
    auto handler = detail::find_method(name);
    if (handler == nullptr) {
        respond(Reply::error(rpc_error::kUnknownMethod, unknown_method(name)));
        return;
    }
    auto params = request.find("params");
    context.notification = notification;
    const auto started = std::chrono::steady_clock::now();
    run_method(handler, context, params == request.end() ? json(nullptr) : *params, respond);
    const auto ended = std::chrono::steady_clock::now();
    context.notification = false;
    context.client.rate.charge(ended - started, ended);
    if (context.worst != nullptr && ended - started > context.worst->time) {
        context.worst->time = ended - started;
        context.worst->method = name;
    }
    if (name != "status") {
        context.status_cache.invalidate();  // what it changed shows in the next status
    }
}

// Collects a batch's replies in request order and sends them as one line once
// the last (possibly asynchronous) member has answered. The line holds at
// most kMaxBatchReplyBytes of replies, so that it always fits a client's
// output limit (Outbox, 256 KiB): a member whose reply would pass that is
// answered with an error naming the limit instead (its work was done, its
// result not sent: a `captures` page is the one reply that large).
class Batch {
  public:
    static constexpr std::size_t kMaxBatchReplyBytes = 128 * 1024;

    Batch(std::size_t members, ReplySink sink, json ids)
        : replies_(members), ids_(std::move(ids)), sink_(std::move(sink)) {}

    ReplySink slot(std::size_t index, const std::shared_ptr<Batch>& self) {
        ++outstanding_;
        return [self, index](std::string reply) { self->fill(index, std::move(reply)); };
    }

    // Called after every member has been dispatched; members that were
    // notifications never answer and leave an empty slot.
    void dispatched() {
        dispatched_ = true;
        finish_if_done();
    }

  private:
    void fill(std::size_t index, std::string reply) {
        if (bytes_ + reply.size() > kMaxBatchReplyBytes) {
            reply = dump(error_object(
                ids_[index], rpc_error::kInvalidRequest,
                fmt::format("this reply ({} bytes) does not fit in the batch's line: a batch's "
                            "replies may hold at most {} bytes; send this request alone or in a "
                            "smaller batch",
                            reply.size(), kMaxBatchReplyBytes)));
        }
        bytes_ += reply.size();
        replies_[index] = std::move(reply);
        --outstanding_;
        finish_if_done();
    }

    void finish_if_done() {
        if (!dispatched_ || outstanding_ > 0 || sent_) {
            return;
        }
        sent_ = true;
        std::string out;
        for (const auto& reply : replies_) {
            if (!reply.empty()) {
                out += out.empty() ? '[' : ',';
                out += reply;
            }
        }
        if (!out.empty()) {
            sink_(out + "]\n");
        }
    }

    std::vector<std::string> replies_;  // empty: a notification's slot
    json ids_;                          // each member's id (null where it has none)
    std::size_t bytes_ = 0;             // of the replies kept
    ReplySink sink_;
    std::size_t outstanding_ = 0;
    bool dispatched_ = false;
    bool sent_ = false;
};

// A well-formed request without id: it runs, and its batch slot stays empty.
bool is_notification(const json& request) {
    return request.is_object() && !request.contains("id") && !envelope_error(request);
}

}  // namespace

namespace detail {

Reply::Reply(const json& result) : text_(dump(result)) {}

Reply Reply::error(int code, std::string message) {
    Reply reply;
    reply.text_ = std::move(message);
    reply.error_code_ = code;
    return reply;
}

Reply Reply::raw(std::string result_text) {
    Reply reply;
    reply.text_ = std::move(result_text);
    return reply;
}

std::string Reply::object(const json& id) const {
    if (error_code_) {
        return dump(error_object(id, *error_code_, text_));
    }
    return "{\"id\":" + dump(id) + ",\"jsonrpc\":\"2.0\",\"result\":" + text_ + '}';
}

}  // namespace detail

void RequestRate::charge(Clock::duration cost, Clock::time_point now) {
    if (!limited() || cost <= kCostPerToken) {
        return;
    }
    bucket_.charge(now, std::chrono::duration<double>(cost - kCostPerToken) /
                            std::chrono::duration<double>(kCostPerToken));
}

std::string error_line(int code, std::string_view message) {
    return detail::json_line(error_object(nullptr, code, message));
}

Dispatcher::Dispatcher(daemon::Api& api, std::function<ServerStats()> stats,
                       StatusCache::Clock::duration status_max_age)
    : api_(api),
      server_stats_(std::move(stats)),
      stats_([this] {
          auto s = server_stats_();
          s.worst_request_us = static_cast<std::uint64_t>(
              std::chrono::duration_cast<std::chrono::microseconds>(worst_.time).count());
          s.worst_method = worst_.method;
          return s;
      }),
      status_cache_(status_max_age) {}

void Dispatcher::handle_line(std::string_view line, ClientState& client, const ReplySink& sink) {
    // Whatever is logged while the request runs (here, in the core, in the
    // reply's delivery) carries the client's journal fields.
    const daemon::ClientLogScope scope(client.info);
    if (base::nested_deeper_than(line, kMaxDepth)) {
        sink(error_line(rpc_error::kParse,
                        fmt::format("parse error: nesting deeper than {} levels", kMaxDepth)));
        return;
    }
    json request;
    try {
        request = json::parse(line);
    } catch (const json::exception& e) {
        // parse_error, but also out_of_range for a number too large for a double.
        sink(error_line(rpc_error::kParse, fmt::format("parse error: {}", e.what())));
        return;
    }
    detail::MethodContext context{api_,          client,    stats_, status_cache_,
                                  channel_host_, captures_, false,  &worst_};
    // A reply may come after this returns (settings): it keeps a copy of the
    // sink, and of who asked, so its delivery is logged with the client's
    // fields too (the groups are not needed for that).
    const daemon::ClientInfo asker{
        client.info.id, client.info.pid, client.info.uid, client.info.gid, {}};
    if (!request.is_array()) {
        run_request(request, context, [sink, asker](std::string reply) {
            const daemon::ClientLogScope reply_scope(asker);
            sink(std::move(reply) + '\n');
        });
        return;
    }
    if (request.empty() || request.size() > kMaxBatch) {
        sink(error_line(rpc_error::kInvalidRequest,
                        fmt::format("a batch must hold 1 to {} requests", kMaxBatch)));
        return;
    }
    json ids = json::array();
    for (const auto& member : request) {
        const auto id = member.is_object() ? member.find("id") : member.end();
        ids.push_back(member.is_object() && id != member.end() ? *id : json(nullptr));
    }
    auto batch = std::make_shared<Batch>(
        request.size(),
        [sink, asker](std::string reply) {
            const daemon::ClientLogScope reply_scope(asker);
            sink(std::move(reply));
        },
        std::move(ids));
    for (std::size_t i = 0; i < request.size(); ++i) {
        if (is_notification(request[i])) {
            run_request(request[i], context, [](const std::string&) {});
        } else {
            run_request(request[i], context, batch->slot(i, batch));
        }
    }
    batch->dispatched();
}

}  // namespace gport::ipc
