#include "http_rules.hpp"

#include <boost/asio/ip/address.hpp>
#include <nlohmann/json.hpp>
#include <optional>

namespace gport::web {
namespace {

// The address a Host names, when it is an IP literal ([...] for IPv6).
std::optional<boost::asio::ip::address> ip_of(std::string_view name) {
    if (name.size() >= 2 && name.front() == '[' && name.back() == ']') {
        name = name.substr(1, name.size() - 2);
    }
    boost::system::error_code ec;
    const auto address = boost::asio::ip::make_address(std::string(name), ec);
    return ec ? std::nullopt : std::optional(address);
}

std::string lower(std::string_view text) {
    std::string out(text);
    for (auto& c : out) {
        c = (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c;
    }
    return out;
}

int hex_digit(char c) {
    if (c >= '0' && c <= '9') {
        return c - '0';
    }
    c = static_cast<char>(c | 0x20);
    return c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1;
}

std::string url_decode(std::string_view text) {
    std::string out;
    for (std::size_t i = 0; i < text.size(); ++i) {
        if (text[i] == '+') {
            out += ' ';
        } else if (text[i] == '%' && i + 2 < text.size() && hex_digit(text[i + 1]) >= 0 &&
                   hex_digit(text[i + 2]) >= 0) {
            out += static_cast<char>(hex_digit(text[i + 1]) * 16 + hex_digit(text[i + 2]));
            i += 2;
        } else {
            out += text[i];
        }
    }
    return out;
}

}  // namespace

bool host_allowed(Context& context, std::string_view host) {
    std::string_view name = host;
    std::string_view port;
    const auto bracket = host.rfind(']');
    const auto colon = host.rfind(':');
    if (colon != std::string_view::npos && (bracket == std::string_view::npos || colon > bracket)) {
        name = host.substr(0, colon);
        port = host.substr(colon + 1);
    }
    const auto lowered = lower(name);
    for (const auto& allowed : context.options.allow_hosts) {
        if (lowered == lower(allowed)) {
            return true;
        }
    }
    if (port != std::to_string(context.port)) {
        return false;
    }
    if (lowered == "localhost") {
        return context.served.has_loopback();
    }
    const auto address = ip_of(lowered);
    return address && context.served.contains(*address);
}

bool origin_allowed(Context& context, std::string_view origin) {
    if (origin.empty()) {
        return true;
    }
    for (std::string_view scheme : {"http://", "https://"}) {
        if (origin.starts_with(scheme)) {
            const auto host = origin.substr(scheme.size());
            return host.find('/') == std::string_view::npos && host_allowed(context, host);
        }
    }
    return false;
}

std::string session_of(const Request& request) {
    const auto header = request[http::field::cookie];
    std::string_view cookies(header.data(), header.size());
    while (!cookies.empty()) {
        const auto end = cookies.find(';');
        auto pair = cookies.substr(0, end);
        cookies.remove_prefix(end == std::string_view::npos ? cookies.size() : end + 1);
        while (!pair.empty() && pair.front() == ' ') {
            pair.remove_prefix(1);
        }
        if (pair.starts_with(kCookieName) && pair.substr(kCookieName.size()).starts_with("=")) {
            return std::string(pair.substr(kCookieName.size() + 1));
        }
    }
    return {};
}

namespace {

// The token of an `Authorization: Bearer <token>` header. The scheme's name
// is case-insensitive (RFC 9110, 11.1: "bearer" is Bearer), and one or more
// spaces follow it.
std::optional<std::string_view> bearer_token(const Request& request) {
    const auto header = request[http::field::authorization];
    const std::string_view authorization(header.data(), header.size());
    const auto space = authorization.find(' ');
    if (space == std::string_view::npos || lower(authorization.substr(0, space)) != "bearer") {
        return std::nullopt;
    }
    auto token = authorization.substr(space);
    token.remove_prefix(std::min(token.find_first_not_of(' '), token.size()));
    return token;
}

}  // namespace

std::optional<Role> authenticate(Context& context, const Request& request) {
    if (const auto token = bearer_token(request)) {
        return role_of(context.tokens, *token);
    }
    if (const auto id = session_of(request); !id.empty()) {
        return context.sessions.find(id);
    }
    return std::nullopt;
}

bool cross_site(const Request& request) {
    const auto header = request["Sec-Fetch-Site"];
    const auto site = lower(std::string_view(header.data(), header.size()));
    return site == "cross-site" || site == "same-site";
}

bool bearer_of(const Request& request) {
    return bearer_token(request).has_value();
}

std::string path_of(std::string_view target) {
    return std::string(target.substr(0, target.find('?')));
}

std::optional<std::string> form_value(std::string_view text, std::string_view name) {
    text = text.substr(text.find('?') == std::string_view::npos ? 0 : text.find('?') + 1);
    while (!text.empty()) {
        const auto end = text.find('&');
        const auto pair = text.substr(0, end);
        text.remove_prefix(end == std::string_view::npos ? text.size() : end + 1);
        if (pair.starts_with(name) && pair.substr(name.size()).starts_with("=")) {
            return url_decode(pair.substr(name.size() + 1));
        }
    }
    return std::nullopt;
}

Response text_response(const Request& request, http::status status, std::string_view type,
                       std::string body) {
    Response response(status, request.version());
    response.set(http::field::content_type, std::string(type));
    response.set(http::field::cache_control, "no-store");
    response.set("X-Content-Type-Options", "nosniff");
    response.set("X-Frame-Options", "DENY");
    // Not no-referrer: under it browsers send "Origin: null" with the page's
    // own POSTs, which the Origin check refuses (docs/web.md, "Security").
    response.set("Referrer-Policy", "same-origin");
    response.set("Content-Security-Policy", std::string(kContentSecurityPolicy));
    response.keep_alive(request.keep_alive());
    response.body() = std::move(body);
    response.prepare_payload();
    return response;
}

Response json_response(const Request& request, http::status status, std::string body) {
    return text_response(request, status, "application/json", std::move(body));
}

Response error_response(const Request& request, http::status status, std::string_view message,
                        std::optional<int> code) {
    const nlohmann::json body = {
        {"error",
         {{"code", code.value_or(static_cast<int>(status))}, {"message", std::string(message)}}}};
    return json_response(request, status,
                         body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
}

Response redirect(const Request& request, std::string_view location) {
    auto response = text_response(request, http::status::see_other, "text/plain", "");
    response.set(http::field::location, std::string(location));
    return response;
}

std::string session_cookie(const std::string& id) {
    return std::string(kCookieName) + "=" + id + "; HttpOnly; SameSite=Strict; Path=/" +
           (id.empty() ? "; Max-Age=0" : "");
}

}  // namespace gport::web
