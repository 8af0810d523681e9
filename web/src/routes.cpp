// Every request's first checks (Host, Origin), the login and logout, the
// page's files and the hand-over to the API and the live WebSocket.
#include <algorithm>
#include <boost/beast/websocket/rfc6455.hpp>
#include <cstdint>

#include "gport/web/assets.hpp"
#include "gport/web/limits.hpp"
#include "http_session.hpp"

namespace gport::web {
namespace {

constexpr char kLoginFile[] = "login.html";
constexpr char kIndexFile[] = "index.html";
constexpr std::string_view kMessageMark = "<!--message-->";  // in login.html

std::string_view header(const Request& request, http::field field) {
    const auto value = request[field];
    return {value.data(), value.size()};
}

// Hex digits as base64 (a CSP hash source is the base64 of the digest).
std::string base64_of_hex(std::string_view hex) {
    static constexpr char kDigits[] =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string bytes;
    for (std::size_t i = 0; i + 1 < hex.size(); i += 2) {
        bytes += static_cast<char>(std::stoi(std::string(hex.substr(i, 2)), nullptr, 16));
    }
    std::string out;
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
        std::uint32_t group = 0;
        for (std::size_t k = 0; k < 3; ++k) {
            group = group << 8 | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0U);
        }
        for (std::size_t k = 0; k < 4; ++k) {
            out += k <= n ? kDigits[(group >> (18 - 6 * k)) & 63] : '=';
        }
    }
    return out;
}

Response asset_response(const Request& request, const Asset& asset, http::status status,
                        std::optional<std::string> body = std::nullopt) {
    auto response = text_response(request, status, asset.content_type,
                                  body ? std::move(*body) : std::string(asset.bytes));
    if (!asset.style_sha256.empty()) {  // its inline <style>, by its hash
        response.set("Content-Security-Policy", std::string(kContentSecurityPolicy) +
                                                    "; style-src 'self' 'sha256-" +
                                                    base64_of_hex(asset.style_sha256) + "'");
    }
    if (request.method() == http::verb::head) {
        response.body().clear();
    }
    return response;
}

std::string html_escaped(std::string_view text) {
    std::string out;
    for (const char c : text) {
        switch (c) {
            case '&':
                out += "&amp;";
                break;
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '"':
                out += "&quot;";
                break;
            default:
                out += c;
        }
    }
    return out;
}

// The login page (or a plain one when web/www has none), with `status`,
// naming the token file.
Response login_page(const Context& context, const Request& request, http::status status) {
    if (const auto* asset = find_asset(kLoginFile)) {
        std::string body(asset->bytes);
        static constexpr std::string_view kMarker = "<!--token-file-->";
        if (const auto at = body.find(kMarker); at != std::string::npos) {
            body.replace(at, kMarker.size(), html_escaped(context.options.token_file));
        }
        return asset_response(request, *asset, status, std::move(body));
    }
    return text_response(request, status, "text/html; charset=utf-8",
                         "<!doctype html><title>gport-web</title>"
                         "<form method=post action=/login><input name=token type=password>"
                         "<button>Log in</button></form>\n");
}

// A browser's own navigation (the login form's POST, /?token= opened): it
// shows what it gets, so a refused login is the login page with a line of
// text in it rather than JSON (scripts, which ask for no HTML, get JSON).
bool navigation(const Request& request) {
    return header(request, http::field::accept).find("text/html") != std::string_view::npos;
}

// The login page with `line` (a fixed text of ours, no markup) above the form.
Response login_page(const Context& context, const Request& request, http::status status,
                    std::string_view line) {
    auto response = login_page(context, request, status);
    auto& body = response.body();
    if (const auto at = body.find(kMessageMark); at != std::string::npos) {
        body.replace(at, kMessageMark.size(),
                     R"(<p class="error" role="alert" data-testid="login-error">)" +
                         std::string(line) + "</p>");
        response.prepare_payload();
    }
    return response;
}

// A refused login: JSON `message`, or for a browser the login page with `line`.
Response login_refusal(const Context& context, const Request& request, http::status status,
                       std::string_view message, std::string_view line) {
    return navigation(request) ? login_page(context, request, status, line)
                               : error_response(request, status, message);
}

// While the failed logins of the window are used up: 429 with Retry-After.
Response too_many_logins(const Context& context, const Request& request, int wait) {
    auto response = login_refusal(context, request, http::status::too_many_requests,
                                  "too many failed logins from your address: try again later",
                                  "too many tries: try again in " + std::to_string(wait) + " s");
    response.set(http::field::retry_after, std::to_string(wait));
    return response;
}

// A wrong or missing token (or login code: `line` says which for a
// browser): 401 and one failure of the peer's, or, beyond its failures,
// 429 after the tarpit delay (counting nothing more).
void refuse_guess(const std::shared_ptr<HttpSession>& session, const Request& request,
                  std::string_view line = "wrong token") {
    auto& context = session->context();
    const auto& peer = session->membership().peer();
    if (const auto wait = context.logins.blocked(peer)) {
        session->send_after(too_many_logins(context, request, *wait), kLoginTarpit);
        return;
    }
    context.logins.failed(peer);
    session->send(login_refusal(context, request, http::status::unauthorized,
                                "wrong or missing token", line));
}

// A login with a token (`secret`) or a one-time code: the cookie and 303
// to /, or 401/429; 403 when a browser says another site's page sent it
// (login CSRF; counts nothing).
void log_in(const std::shared_ptr<HttpSession>& session, const Request& request,
            const std::optional<std::string>& secret, const std::optional<std::string>& code = {}) {
    if (cross_site(request)) {
        session->send(login_refusal(
            session->context(), request, http::status::forbidden,
            "login from another site's page refused (Sec-Fetch-Site): open this server's page",
            "a login from another site's page is refused: log in here"));
        return;
    }
    auto& context = session->context();
    const auto role = secret ? role_of(context.tokens, *secret)
                      : code ? context.codes.redeem(context.tokens, *code)
                             : std::nullopt;
    if (!role) {
        refuse_guess(session, request,
                     code ? "this login link was used already or has expired: run gport-web "
                            "--print-url for a new one, or log in with a token"
                          : "wrong token");
        return;
    }
    session->membership().authenticate();
    auto response = redirect(request, "/");
    response.set(http::field::set_cookie, session_cookie(context.sessions.open(*role)));
    session->send(std::move(response));
}

void page(const std::shared_ptr<HttpSession>& session, const Request& request,
          std::optional<Role> role) {
    if (request.method() != http::verb::get && request.method() != http::verb::head) {
        session->send(error_response(request, http::status::method_not_allowed,
                                     "only GET and HEAD serve the page"));
        return;
    }
    const auto path = path_of(target_of(request));
    if (path == "/") {
        if (const auto token = form_value(target_of(request), "token")) {
            log_in(session, request, token);
        } else if (const auto code = form_value(target_of(request), "code")) {
            log_in(session, request, std::nullopt, code);
        } else if (!role && !session_of(request).empty()) {
            session->send(login_page(session->context(), request, http::status::ok,
                                     "your session has ended (it went unused, or you logged "
                                     "out): log in again"));
        } else if (!role || !find_asset(kIndexFile)) {
            session->send(login_page(session->context(), request, http::status::ok));
        } else {
            session->send(asset_response(request, *find_asset(kIndexFile), http::status::ok));
        }
        return;
    }
    const auto* asset = find_asset(std::string_view(path).substr(1));
    if (asset && asset->path == kLoginFile) {
        session->send(login_page(session->context(), request, http::status::ok));
    } else if (!role) {
        session->send(error_response(request, http::status::unauthorized, "log in first"));
    } else if (!asset) {
        session->send(error_response(request, http::status::not_found, "no such page"));
    } else {
        session->send(asset_response(request, *asset, http::status::ok));
    }
}

// The API within its peer address's rate (a stop always goes); beyond it,
// 429 with Retry-After, sent after the tarpit.
void api_within_rate(const std::shared_ptr<HttpSession>& session, Request request, Role role) {
    const bool stop =
        request.method() == http::verb::post && path_of(target_of(request)) == "/api/stop";
    if (!stop) {
        if (const auto wait = session->context().api_rates.take(session->membership().peer())) {
            auto response =
                error_response(request, http::status::too_many_requests,
                               "too many requests from your address: at most " +
                                   std::to_string(static_cast<int>(kApiRequestsPerSecond)) +
                                   " a second; try again in " + std::to_string(*wait) + " s");
            response.set(http::field::retry_after, std::to_string(*wait));
            // After the tarpit (a timer; the loop goes on): a connection
            // past its rate asks at most once a second, however fast it
            // sends, so a flood costs gport-web little CPU.
            session->send_after(std::move(response), kLoginTarpit);
            return;
        }
    }
    api(session, std::move(request), role);
}

void log_out(const std::shared_ptr<HttpSession>& session, const Request& request) {
    if (const auto id = session_of(request); !id.empty()) {
        session->context().sessions.close(id);
    }
    auto response = redirect(request, "/");
    response.set(http::field::set_cookie, session_cookie(""));
    session->send(std::move(response));
}

}  // namespace

void route(const std::shared_ptr<HttpSession>& session, Request request) {
    auto& context = session->context();
    if (!host_allowed(context, header(request, http::field::host))) {
        session->send(error_response(request, http::status::forbidden,
                                     "foreign Host: use --allow-host to serve another name"));
        return;
    }
    if (!origin_allowed(context, header(request, http::field::origin))) {
        session->send(error_response(request, http::status::forbidden, "foreign Origin"));
        return;
    }
    const auto path = path_of(target_of(request));
    const auto role = authenticate(context, request);
    if (!role && bearer_of(request)) {
        refuse_guess(session, request);
        return;
    }
    if (role) {
        session->membership().authenticate();
    }
    const bool post = request.method() == http::verb::post;
    if (boost::beast::websocket::is_upgrade(request) && path == "/api/live") {
        if (!role) {
            session->send(error_response(request, http::status::unauthorized, "log in first"));
        } else {
            session->upgrade(std::move(request), *role);
        }
    } else if (path == "/login" && post) {
        log_in(session, request, form_value(request.body(), "token"));
    } else if (path == "/logout" && post) {
        log_out(session, request);
    } else if (path.starts_with("/api/")) {
        if (!role) {
            session->send(error_response(request, http::status::unauthorized, "log in first"));
        } else {
            api_within_rate(session, std::move(request), *role);
        }
    } else {
        page(session, request, role);
    }
}

}  // namespace gport::web
