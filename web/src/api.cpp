// The HTTP API (docs/web.md, "HTTP API"): each path checked (method, role,
// body) and passed to gportd through the gateway.
#include <charconv>
#include <nlohmann/json.hpp>

#include "gport/contract/names.hpp"
#include "gport/version.hpp"
#include "http_session.hpp"
#include "json_text.hpp"

namespace gport::web {
namespace {

using nlohmann::json;
namespace method = contract::method;

enum class Kind { kNumber, kInteger, kBool };

struct Field {
    const char* name;
    Kind kind;
};

struct Route {
    const char* path;
    http::verb verb;
    const char* method;  // gportd's
    std::vector<Field> fields;
};

const std::vector<Route>& routes() {
    static const std::vector<Route> kRoutes = {
        {"/api/status", http::verb::get, method::kStatus, {}},
        {"/api/settings", http::verb::get, method::kGetSettings, {}},
        {"/api/limits", http::verb::get, method::kLimits, {}},
        {"/api/settings",
         http::verb::post,
         method::kSetSettings,
         {{"dead_zone", Kind::kInteger},
          {"follow_speed", Kind::kInteger},
          {"inverted", Kind::kBool}}},
        {"/api/angle",
         http::verb::post,
         method::kAngle,
         {{"pitch", Kind::kNumber},
          {"yaw", Kind::kNumber},
          {"roll", Kind::kNumber},
          {"wait", Kind::kBool}}},
        {"/api/center", http::verb::post, method::kCenter, {{"wait", Kind::kBool}}},
        {"/api/stop", http::verb::post, method::kStop, {}},
        {"/api/photo", http::verb::post, method::kPhoto, {}},
        {"/api/record",
         http::verb::post,
         method::kRecord,
         {{"on", Kind::kBool}, {"force", Kind::kBool}}},
    };
    return kRoutes;
}

bool fits(const json& value, Kind kind) {
    switch (kind) {
        case Kind::kNumber:
            return value.is_number();
        case Kind::kInteger:
            return value.is_number_integer();
        case Kind::kBool:
            return value.is_boolean();
    }
    return false;
}

const char* kind_name(Kind kind) {
    return kind == Kind::kBool      ? "true or false"
           : kind == Kind::kInteger ? "an integer"
                                    : "a number";
}

// The params for gportd from a JSON body (empty: none), or the problem.
std::variant<json, std::string> params_of(const std::string& body,
                                          const std::vector<Field>& fields) {
    const auto params = body.empty() ? json::object() : json::parse(body, nullptr, false);
    if (!params.is_object()) {
        return std::string("the body must be a JSON object");
    }
    for (const auto& [key, value] : params.items()) {
        const std::string& name = key;  // clang 14 cannot capture a structured binding
        const auto it = std::find_if(fields.begin(), fields.end(),
                                     [&](const Field& f) { return name == f.name; });
        if (it == fields.end()) {
            std::string allowed;
            for (const auto& f : fields) {
                allowed += std::string(allowed.empty() ? "" : ", ") + f.name;
            }
            return "unknown field '" + key + "'; allowed: " + (allowed.empty() ? "none" : allowed);
        }
        if (!fits(value, it->kind)) {
            return "field '" + key + "' must be " + kind_name(it->kind);
        }
    }
    return params;
}

// gportd's answer as the HTTP answer: its result, or its refusal.
client::Handler<std::string> answer(const std::shared_ptr<HttpSession>& session,
                                    const Request& request,
                                    std::function<std::string(const std::string&)> shape = {}) {
    return [session, request, shape](std::optional<client::Error> error,
                                     const std::string& result) {
        if (!error) {
            session->send(json_response(request, http::status::ok, shape ? shape(result) : result));
            return;
        }
        const bool params = error->is(client::ErrorCode::kInvalidParams);
        const bool busy = error->is(client::ErrorCode::kTooManyRequests);
        const bool gone =
            error->is(client::ErrorCode::kTransport) || error->is(client::ErrorCode::kTimeout);
        session->send(
            error_response(request,
                           params ? http::status::bad_request
                           : busy ? http::status::service_unavailable
                                  : http::status::bad_gateway,
                           gone ? "gportd is not reachable: " + error->message() : error->message(),
                           error->code()));
    };
}

std::string version_of(const std::string& status) {
    const auto s = json::parse(status, nullptr, false);
    return json_text(
        {{"version", std::string(kVersion)},
         {"daemon_version", s.is_object() ? s.value("daemon_version", json()) : json()},
         {"api_version", s.is_object() ? s.value("api_version", json()) : json()},
         {"config_file", s.is_object() ? s.value("config_file", json()) : json()}});
}

std::optional<std::uint64_t> number_of(const std::optional<std::string>& text) {
    std::uint64_t value = 0;
    if (!text || text->empty()) {
        return std::nullopt;
    }
    const auto [end, ec] = std::from_chars(text->data(), text->data() + text->size(), value);
    return ec == std::errc() && end == text->data() + text->size() ? std::optional(value)
                                                                   : std::nullopt;
}

// Reads without params from the shared snapshot, a stop ahead of
// everything, other commands in order (docs/web.md, "The stop comes first").
void pass_on(Gateway& gateway, const std::string& name, std::string params, Reply reply) {
    if (name == method::kStop) {
        gateway.stop(std::move(reply));
    } else if (name == method::kStatus || name == method::kLimits || name == method::kGetSettings) {
        gateway.snapshot(name, std::move(reply));
    } else {
        gateway.command(name, std::move(params), std::move(reply));
    }
}

void captures_page(const std::shared_ptr<HttpSession>& session, const Request& request) {
    const auto since_text = form_value(target_of(request), "since");
    const auto limit_text = form_value(target_of(request), "limit");
    const auto since = number_of(since_text);
    const auto limit = number_of(limit_text);
    if ((since_text && !since) || (limit_text && (!limit || *limit > 100000))) {
        session->send(
            error_response(request, http::status::bad_request,
                           "since and limit must be whole numbers (limit at most 100000)"));
        return;
    }
    json params = {{"since", since.value_or(0)}};
    if (limit) {
        params["limit"] = *limit;
    }
    session->context().gateway.read(method::kCaptures, json_text(params), answer(session, request));
}

}  // namespace

void api(const std::shared_ptr<HttpSession>& session, Request request, Role role) {
    const auto path = path_of(target_of(request));
    const bool get = request.method() == http::verb::get;
    if (path == "/api/version" && get) {
        session->context().gateway.snapshot(method::kStatus, answer(session, request, version_of));
        return;
    }
    if (path == "/api/captures" && get) {
        captures_page(session, request);
        return;
    }
    if ((path == "/api/captures.csv" || path == "/api/captures.geojson") && get) {
        download_captures(session, request, path.ends_with(".geojson"));
        return;
    }
    bool known = false;
    for (const auto& route : routes()) {
        known = known || path == route.path;
        if (path != route.path || request.method() != route.verb) {
            continue;
        }
        if (route.verb == http::verb::post && role != Role::kControl) {
            session->send(error_response(request, http::status::forbidden,
                                         "a view login cannot change the gimbal"));
            return;
        }
        // Reading the settings is an exchange of frames with the gimbal,
        // which gportd refuses its own read-only clients, and each one
        // takes one of the few settings requests gportd queues.
        if (route.method == std::string_view(method::kGetSettings) && role != Role::kControl) {
            session->send(error_response(
                request, http::status::forbidden,
                "a view login cannot read the gimbal's settings (reading them is an exchange "
                "with the gimbal, a control login's)"));
            return;
        }
        auto params = params_of(request.body(), route.fields);
        if (auto* problem = std::get_if<std::string>(&params)) {
            session->send(error_response(request, http::status::bad_request, *problem));
            return;
        }
        pass_on(session->context().gateway, route.method, json_text(std::get<json>(params)),
                answer(session, request));
        return;
    }
    const bool other = path == "/api/version" || path.starts_with("/api/captures");
    session->send(
        known || other
            ? error_response(request, http::status::method_not_allowed, "method not allowed")
            : error_response(request, http::status::not_found, "no such API path"));
}

}  // namespace gport::web
