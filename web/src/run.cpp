#include "gport/web/run.hpp"

#include <boost/asio/signal_set.hpp>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include "acceptor.hpp"
#include "context.hpp"
#include "gport/base/exit_status.hpp"
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

// True when stdout goes to systemd's journal (a service).
bool under_journal() {
    const char* stream = std::getenv("JOURNAL_STREAM");
    return stream && *stream;
}

int serve(Options options, TokenFile tokens) {
    boost::asio::io_context io;
    Context context(io, options, std::move(tokens.tokens));
    std::shared_ptr<Acceptor> listener;
    try {
        const boost::asio::ip::tcp::endpoint endpoint(
            boost::asio::ip::make_address(options.address), options.port);
        listener = std::make_shared<Acceptor>(context, endpoint);
    } catch (const boost::system::system_error& e) {
        std::cerr << "gport-web: cannot listen on " << options.address << ":" << options.port
                  << ": " << e.code().message() << "\n";
        return kExitOsError;
    }
    context.port = listener->local().port();
    const auto urls = urls_of(listener->local());
    for (const auto& url : urls) {
        std::cout << "gport-web: serving " << url << "\n";
    }
    for (const auto& url : urls) {
        if (tokens.created && under_journal()) {  // no token in the journal
            std::cout << "gport-web: created " << options.token_file << ": open " << url
                      << "?token=TOKEN to log in, TOKEN from the file (sudo cat "
                      << options.token_file << ")\n";
        } else if (tokens.created) {
            std::cout << "gport-web: open " << url << "?token=" << *tokens.created
                      << " to log in\n";
        }
    }
    std::cout.flush();
    // A signal closes everything; io.run() returns once nothing is pending,
    // before any object the handlers use is destroyed.
    boost::asio::signal_set signals(io, SIGINT, SIGTERM);
    signals.async_wait([&](boost::system::error_code, int) {
        listener->stop();
        context.gateway.close();
        const auto closers = context.closers;
        for (const auto& [connection, close] : closers) {
            close();
        }
    });
    listener->start();
    context.gateway.start();
    io.run();
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
        tokens = load_tokens(parsed.options->token_file);
    } catch (const std::exception& e) {
        std::cerr << "gport-web: " << e.what() << "\n";
        return kExitNoInput;
    }
    return serve(std::move(*parsed.options), std::move(tokens));
}

}  // namespace gport::web
