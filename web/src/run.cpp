#include "gport/web/run.hpp"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <boost/asio/signal_set.hpp>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "acceptor.hpp"
#include "context.hpp"
#include "gport/base/exit_status.hpp"
#include "gport/web/login_codes.hpp"
#include "gport/web/options.hpp"
#include "served_addresses.hpp"

namespace gport::web {
namespace {

std::string url_of(const boost::asio::ip::address& address, unsigned short port) {
    const auto host = address.is_v6() ? "[" + address.to_string() + "]" : address.to_string();
    return "http://" + host + ":" + std::to_string(port) + "/";
}

// The links to print: one per address gport-web is reached at (listening on
// 0.0.0.0 or ::, the interfaces' addresses, loopback last: an
// http://0.0.0.0:PORT/ link opens nothing in a phone's browser).
std::vector<std::string> urls_of(const boost::asio::ip::tcp::endpoint& endpoint) {
    std::vector<std::string> urls;
    for (const auto& address : served_addresses(endpoint.address())) {
        if (!(address.is_v6() && address.to_v6().is_link_local())) {  // needs a zone in a URL
            urls.push_back(url_of(address, endpoint.port()));
        }
    }
    if (urls.empty()) {
        urls.push_back(url_of(endpoint.address(), endpoint.port()));
    }
    return urls;
}

std::string listen_text(const Options& options) {
    const auto address = boost::asio::ip::make_address(options.address);
    return (address.is_v6() ? "[" + options.address + "]" : options.address) + ":" +
           std::to_string(options.port);
}

// True when stdout goes to systemd's journal (a service).
bool under_journal() {
    const char* stream = std::getenv("JOURNAL_STREAM");
    return stream && *stream;
}

// How to log in, at every start: a one-time link for each address (a code
// that works once, for kLoginCodeLifetime: the address left in the
// browser's history logs no one in), and where the token is. Under the
// journal no code or token is written: the command that prints a link is.
void print_login(const Options& options, const std::vector<std::string>& urls,
                 const TokenFile& tokens) {
    const auto& file = options.token_file;
    if (tokens.created) {
        std::cout << "gport-web: created " << file << " with a control token\n";
    }
    if (under_journal()) {
        std::cout << "gport-web: to log in, run `gport-web --print-url --listen "
                  << listen_text(options) << " --token-file " << file << "` as a user who may read "
                  << file << " (a one-time link), or use a token "
                  << "from that file\n";
        return;
    }
    for (const auto& url : urls) {
        std::cout << "gport-web: open " << url << "?code=" << make_login_code(tokens.tokens.front())
                  << " to log in (works once, for 10 minutes; the tokens are in " << file << ")\n";
    }
}

void persist(Context& context) {
    const auto dir = std::filesystem::path(context.options.token_file).parent_path();
    for (const auto& problem : {context.sessions.persist(dir / "sessions"),
                                context.codes.persist(dir / "login-codes-used")}) {
        if (!problem.empty()) {
            spdlog::warn("{}; starting without it (replaced at the next login)", problem);
        }
    }
}

int serve(Options options, TokenFile tokens) {
    boost::asio::io_context io;
    std::optional<boost::asio::ip::tcp::acceptor> listening;
    try {
        listening =
            listen_on(io, boost::asio::ip::tcp::endpoint(
                              boost::asio::ip::make_address(options.address), options.port));
    } catch (const boost::system::system_error& e) {
        std::cerr << "gport-web: cannot listen on " << options.address << ":" << options.port
                  << ": " << e.code().message() << "\n";
        return kExitOsError;
    }
    Context context(io, options, tokens.tokens, listening->local_endpoint().port());
    persist(context);
    auto listener = std::make_shared<Acceptor>(context, std::move(*listening));
    const auto urls = urls_of(listener->local());
    for (const auto& url : urls) {
        std::cout << "gport-web: serving " << url << "\n";
    }
    print_login(options, urls, tokens);
    std::cout.flush();
    // A signal closes everything; io.run() returns once nothing is pending,
    // before any object the handlers use is destroyed.
    boost::asio::signal_set signals(io, SIGINT, SIGTERM);
    signals.async_wait([&](boost::system::error_code, int) {
        listener->stop();
        context.gateway.close();
        context.registry.close_all();
    });
    listener->start();
    context.gateway.start();
    io.run();
    if (const auto problem = context.sessions.save(); !problem.empty()) {
        spdlog::warn("sessions not kept: {}", problem);
    }
    return kExitOk;
}

// --print-url: the links of a running gport-web, from its token file
// (never created here).
int print_urls(const Options& options) {
    if (::access(options.token_file.c_str(), F_OK) != 0) {
        std::cerr << "gport-web: no token file " << options.token_file
                  << ": gport-web makes it at its first start (or give --token-file)\n";
        return kExitNoInput;
    }
    const auto tokens = load_tokens(options.token_file);
    const boost::asio::ip::tcp::endpoint endpoint(boost::asio::ip::make_address(options.address),
                                                  options.port);
    for (const auto& url : urls_of(endpoint)) {
        std::cout << url << "?code=" << make_login_code(tokens.tokens.front()) << "\n";
    }
    return kExitOk;
}

}  // namespace

int run(std::span<const std::string> args) {
    std::signal(SIGPIPE, SIG_IGN);
    Parsed parsed;
    try {
        parsed = parse_options(args);
    } catch (const std::invalid_argument& e) {
        std::cerr << "gport-web: " << e.what() << "\n";
        return kExitUsage;
    }
    if (!parsed.options) {
        std::cout << parsed.text;
        return kExitOk;
    }
    TokenFile tokens;
    try {
        if (parsed.options->print_url) {
            return print_urls(*parsed.options);
        }
        tokens = load_tokens(parsed.options->token_file);
    } catch (const std::exception& e) {
        std::cerr << "gport-web: " << e.what() << "\n";
        return kExitNoInput;
    }
    return serve(std::move(*parsed.options), std::move(tokens));
}

}  // namespace gport::web
