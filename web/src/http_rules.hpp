// The rules every request passes (docs/web.md, "Security"): the Host and
// Origin checks, the login (Bearer token or session cookie), and the
// helpers that read a request and make a response.
#pragma once

#include <boost/beast/http.hpp>
#include <optional>
#include <string>
#include <string_view>

#include "context.hpp"

namespace gport::web {

namespace http = boost::beast::http;
using Request = http::request<http::string_body>;
using Response = http::response<http::string_body>;

inline constexpr std::string_view kCookieName = "gport_session";
// Every answer's policy (docs/web.md, "What the page needs from the server").
inline constexpr std::string_view kContentSecurityPolicy =
    "default-src 'self'; connect-src 'self'; base-uri 'none'; form-action 'self'; "
    "frame-ancestors 'none'";

// A Host header naming this server: with the port served, one of the
// addresses it is reached at (served_addresses.hpp) or localhost when one of
// them is a loopback address; or an --allow-host name (any port).
bool host_allowed(Context& context, std::string_view host);
// An Origin header of this server (http:// or https:// and an allowed
// host), or none at all (a script, not a browser).
bool origin_allowed(Context& context, std::string_view origin);

// True when the request carries an Authorization: Bearer token.
bool bearer_of(const Request& request);
// The role of the request's Bearer token or session cookie (a wrong token is
// the caller's to count: routes.cpp).
std::optional<Role> authenticate(Context& context, const Request& request);
// True when a browser says another site's page sent the request
// (Sec-Fetch-Site: cross-site or same-site; none or same-origin: false, as
// for clients that send no such header).
bool cross_site(const Request& request);
std::string session_of(const Request& request);

// The request's target ("/api/captures?since=3") and its path.
inline std::string_view target_of(const Request& request) {
    const auto target = request.target();
    return {target.data(), target.size()};
}
std::string path_of(std::string_view target);
// The decoded value of `name` in a query string or an
// application/x-www-form-urlencoded body.
std::optional<std::string> form_value(std::string_view text, std::string_view name);

Response text_response(const Request& request, http::status status, std::string_view type,
                       std::string body);
Response json_response(const Request& request, http::status status, std::string body);
// {"error":{"code":C,"message":M}}; C is gportd's code, else the HTTP status.
Response error_response(const Request& request, http::status status, std::string_view message,
                        std::optional<int> code = std::nullopt);
Response redirect(const Request& request, std::string_view location);
// The Set-Cookie value of a session (empty id: the cookie's removal).
std::string session_cookie(const std::string& id);

}  // namespace gport::web
