#include "gport/web/options.hpp"

#include <boost/asio/ip/address.hpp>
#include <charconv>
#include <cstdlib>
#include <stdexcept>

#include "gport/base/args.hpp"
#include "gport/client/client.hpp"
#include "gport/contract/names.hpp"
#include "gport/version.hpp"
#include "gport/web/limits.hpp"

namespace gport::web {
namespace {

constexpr char kFooter[] =
    "Exit status: 0 stopped by a signal (or --print-url done), 64 bad command line, 66 token "
    "file refused (or, with --print-url, missing), 71 cannot listen.";

std::string getenv_text(const char* name) {
    const char* value = std::getenv(name);
    return value ? value : "";
}

std::optional<std::string> check_listen(std::string_view text) {
    if (parse_listen(text)) {
        return std::nullopt;
    }
    return "expected ADDR:PORT with an IP address and a port from 0 to 65535 (0: any free "
           "port), e.g. 127.0.0.1:8790 or [::1]:8790; got '" +
           std::string(text) + "'";
}

std::optional<std::string> check_host(std::string_view text) {
    if (!text.empty() && text.find_first_of(" /\\@") == std::string_view::npos) {
        return std::nullopt;
    }
    return "expected a host name (no scheme, path or spaces); got '" + std::string(text) + "'";
}

}  // namespace

std::optional<std::pair<std::string, unsigned short>> parse_listen(std::string_view text) {
    const auto colon = text.rfind(':');
    if (colon == std::string_view::npos) {
        return std::nullopt;
    }
    auto host = text.substr(0, colon);
    const auto port_text = text.substr(colon + 1);
    if (host.size() >= 2 && host.front() == '[' && host.back() == ']') {
        host = host.substr(1, host.size() - 2);
    }
    unsigned port = 0;
    const auto [end, ec] = std::from_chars(port_text.begin(), port_text.end(), port);
    boost::system::error_code bad;
    boost::asio::ip::make_address(std::string(host), bad);
    if (ec != std::errc() || end != port_text.end() || port_text.empty() || port > 65535 || bad) {
        return std::nullopt;
    }
    return std::make_pair(std::string(host), static_cast<unsigned short>(port));
}

std::string default_token_file(std::string (*env)(const char* name)) {
    if (const auto state = env("STATE_DIRECTORY"); !state.empty()) {
        return state.substr(0, state.find(':')) + "/token";
    }
    return env("HOME") + "/.config/gport-web/token";
}

Parsed parse_options(std::span<const std::string> argv, std::string (*env)(const char* name)) {
    env = env ? env : getenv_text;
    Options options;
    options.socket = client::Client::default_socket(env(contract::kSocketEnv).c_str());
    std::string listen = "127.0.0.1:" + std::to_string(kDefaultPort);
    CLI::App app("gport-web: the gimbal in a browser (docs/web.md)", "gport-web");
    args::configure(app, kFooter);
    app.allow_extras();
    app.add_option("--socket", options.socket,
                   "gportd's socket (default $GPORT_SOCKET, else " +
                       std::string(contract::kDefaultSocket) + ")")
        ->type_name("PATH");
    app.add_option("--listen", listen, "where to serve (default 127.0.0.1:8790, loopback only)")
        ->type_name("ADDR:PORT")
        ->check(args::check_with(check_listen));
    app.add_option("--token-file", options.token_file,
                   "the login tokens (default $STATE_DIRECTORY/token, else "
                   "~/.config/gport-web/token)")
        ->type_name("FILE");
    app.add_option("--allow-host", options.allow_hosts,
                   "another name the page may be reached by (Host and Origin)")
        ->type_name("NAME")
        ->check(args::check_with(check_host))
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
    app.add_flag("--print-url", options.print_url,
                 "print a one-time login link (10 minutes, once) for the gport-web serving "
                 "--listen with --token-file, and exit");
    std::vector<std::string> reversed(argv.rbegin(), argv.rend());
    try {
        app.parse(reversed);
    } catch (const CLI::CallForHelp&) {
        return Parsed{std::nullopt, app.help()};
    } catch (const CLI::CallForVersion& version) {
        return Parsed{std::nullopt, std::string(version.what()) + "\n"};
    } catch (const CLI::ParseError& error) {
        throw std::invalid_argument(args::message_of(error));
    }
    if (auto problem = args::leftover_problem(app); !problem.empty()) {
        throw std::invalid_argument(problem);
    }
    const auto where = parse_listen(listen);
    options.address = where->first;
    options.port = where->second;
    if (options.print_url && options.port == 0) {
        throw std::invalid_argument(
            "--print-url needs the port gport-web serves (--listen ADDR:PORT, not port 0)");
    }
    if (options.token_file.empty()) {
        options.token_file = default_token_file(env);
    }
    return Parsed{options, ""};
}

}  // namespace gport::web
